// The geometry queries answered by looping over every segment: the test oracle for GeometryTree.
// Same contracts (and the same per-segment primitives, so ties resolve identically); O(segments).
#pragma once
#include <vector>

#include "geometry/geometry.hpp"
#include "geometry/geometry_tree.hpp"

namespace pdmesh::brute_force {

ClosestHit closest(const Geometry& g, Vec2 p);
// The closest segment by the least squared distance (h.distance * h.distance), then the lowest index:
// FeatureSize::closest's rule.
ClosestHit closest_by_square(const Geometry& g, Vec2 p);
ClosestHit closest_on_curve(const Geometry& g, Vec2 p, int curve);
void closest_per_curve(const Geometry& g, Vec2 p, std::vector<ClosestHit>& out);
bool inside(const Geometry& g, Vec2 p);
bool crosses_boundary(const Geometry& g, Vec2 a, Vec2 b);

}  // namespace pdmesh::brute_force
