// Robust geometric predicates: adaptive exact arithmetic after Shewchuk (1997), written here.
// The sign of each result is exact for any double input; no epsilon tests anywhere in pdmesh.
#pragma once
#include "core/vec2.hpp"

namespace pdmesh {

// > 0 if a, b, c are in counter-clockwise order, < 0 if clockwise, 0 if collinear.
// The magnitude approximates twice the signed triangle area.
double orient2d(Vec2 a, Vec2 b, Vec2 c);

// > 0 if d lies inside the circle through a, b, c (given counter-clockwise), < 0 outside, 0 on it.
double incircle(Vec2 a, Vec2 b, Vec2 c, Vec2 d);

// Exact tests built on orient2d.
// True when closed segments ab and cd share at least one point.
bool segments_intersect(Vec2 a, Vec2 b, Vec2 c, Vec2 d);
// True when the open segments ab and cd cross at a single interior point of both (a proper crossing).
bool segments_cross_properly(Vec2 a, Vec2 b, Vec2 c, Vec2 d);

}  // namespace pdmesh
