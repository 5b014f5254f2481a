// Projection onto one curve: the closest point of a curve within a range of arc positions, with its
// arc position and tangent. What boundary handling (sim/) and the cleanup (cleanup/) slide boundary
// nodes along.
#pragma once
#include "core/vec2.hpp"
#include "geometry/geometry.hpp"

namespace pdmesh {

// A point on one curve, found by a restricted closest-point search.
struct CurvePoint {
  Vec2 p;
  double arc = 0.0;  // arc-length position from the curve's first point
  Vec2 tangent;      // unit tangent (at a vertex: the normalised mean of both segments' tangents)
  double distance = 0.0;
};

// Closest point of curve `curve` to p among the points with arc position in [arc_lo, arc_hi]
// (ties: lowest segment).
CurvePoint closest_on_curve_range(const Curve& curve, Vec2 p, double arc_lo, double arc_hi);

}  // namespace pdmesh
