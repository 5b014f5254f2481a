// closest_on_segment's body as an inline function, for the searches that call it in their inner loop
// (the geometry tree, the curve scan): the exported closest_on_segment is this too, so every caller
// computes the same bits. Internal to host/geometry.
#pragma once
#include <algorithm>
#include <cmath>

#include "geometry/geometry_tree.hpp"

namespace pdmesh::detail {

// Inlined into the searches (called, each hit would return through memory).
inline __attribute__((always_inline)) ClosestHit closest_on_segment_inline(Vec2 p, const Segment& s, int index) {
  const Vec2 ab = s.b - s.a;
  const double len2 = norm2(ab);
  double t = len2 > 0.0 ? dot(p - s.a, ab) / len2 : 0.0;
  t = std::clamp(t, 0.0, 1.0);
  const Vec2 q = t == 0.0 ? s.a : t == 1.0 ? s.b : s.a + t * ab;
  ClosestHit hit{index, q, norm(p - q), t};
  // The projection rounds, so a point exactly on the segment would get a distance of a few ulps.
  // Snap it to exactly 0 (decided by the exact predicate) so that "on the boundary" means d == 0.
  if (hit.distance != 0.0) {
    // std::max, not std::fmax (a library call, not inlined, on the hot path of every spacing
    // evaluation): the tree's segments are finite, and a NaN in p makes hit.distance NaN, which
    // fails the test below whatever scale is.
    const double scale =
        std::max(std::max(std::fabs(p.x), std::fabs(p.y)),
                 std::max(std::max(std::fabs(s.a.x), std::fabs(s.a.y)), std::max(std::fabs(s.b.x), std::fabs(s.b.y))));
    if (hit.distance <= 1e-12 * scale && point_on_segment(p, s.a, s.b)) {
      hit.point = p;
      hit.distance = 0.0;
    }
  }
  return hit;
}

}  // namespace pdmesh::detail
