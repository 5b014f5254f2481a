// Brute-force geometry queries (the oracle for GeometryTree): every segment is examined.
#include "geometry/brute_force_queries.hpp"

namespace pdmesh::brute_force {

namespace {

// Keeps the closer hit; exact ties go to the lower segment index.
void keep_closer(ClosestHit& best, const ClosestHit& h) {
  if (best.segment < 0 || h.distance < best.distance || (h.distance == best.distance && h.segment < best.segment))
    best = h;
}

}  // namespace

ClosestHit closest(const Geometry& g, Vec2 p) {
  ClosestHit best;
  for (std::size_t i = 0; i < g.segments.size(); ++i)
    keep_closer(best, closest_on_segment(p, g.segments[i], static_cast<int>(i)));
  return best;
}

ClosestHit closest_by_square(const Geometry& g, Vec2 p) {
  ClosestHit best;
  double best2 = 0.0;
  for (std::size_t i = 0; i < g.segments.size(); ++i) {
    const ClosestHit h = closest_on_segment(p, g.segments[i], static_cast<int>(i));
    const double d2 = h.distance * h.distance;
    if (best.segment < 0 || d2 < best2 || (d2 == best2 && h.segment < best.segment)) {
      best2 = d2;
      best = h;
    }
  }
  return best;
}

ClosestHit closest_on_curve(const Geometry& g, Vec2 p, int curve) {
  ClosestHit best;
  for (std::size_t i = 0; i < g.segments.size(); ++i)
    if (g.segments[i].curve == curve) keep_closer(best, closest_on_segment(p, g.segments[i], static_cast<int>(i)));
  return best;
}

void closest_per_curve(const Geometry& g, Vec2 p, std::vector<ClosestHit>& out) {
  out.assign(g.curves.size(), ClosestHit{});
  for (std::size_t i = 0; i < g.segments.size(); ++i)
    keep_closer(out[g.segments[i].curve], closest_on_segment(p, g.segments[i], static_cast<int>(i)));
}

bool inside(const Geometry& g, Vec2 p) {
  bool in = false;
  for (const Segment& s : g.segments) {
    const int r = ray_crossing(p, s.a, s.b);
    if (r == 2) return true;
    if (r == 1) in = !in;
  }
  return in;
}

bool crosses_boundary(const Geometry& g, Vec2 a, Vec2 b) {
  for (const Segment& s : g.segments)
    if (move_touches_segment(a, b, s.a, s.b)) return true;
  return false;
}

}  // namespace pdmesh::brute_force
