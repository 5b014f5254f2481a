// The boundary intersection check of build_geometry (uniform grid + exact predicates) and the small
// exact point tests (ray crossings, point on segment) the rest of build_geometry uses.
#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

#include <fmt/format.h>

#include "core/errors.hpp"
#include "core/predicates.hpp"
#include "geometry/geometry_detail.hpp"

namespace pdmesh::detail {

std::string where(const std::string& file, int line) {
  if (file.empty()) return fmt::format("curve input line {}", line);
  return fmt::format("{}:{}", file, line);
}

std::string format_point(Vec2 p) { return fmt::format("({}, {})", p.x, p.y); }

int ray_crossings(const std::vector<Segment>& segments, const std::vector<int>& which, Vec2 p) {
  int crossings = 0;
  for (const int s : which) {
    const Vec2 a = segments[s].a;
    const Vec2 b = segments[s].b;
    // Half-open rule in y so a ray through a vertex counts it once.
    if ((a.y > p.y) == (b.y > p.y)) continue;
    const double o = orient2d(a, b, p);
    // Upward edge: the crossing is right of p when p is left of a->b; downward: the opposite.
    if (b.y > a.y ? o > 0 : o < 0) ++crossings;
  }
  return crossings;
}

namespace {

bool in_box(Vec2 a, Vec2 b, Vec2 p) {
  return std::min(a.x, b.x) <= p.x && p.x <= std::max(a.x, b.x) && std::min(a.y, b.y) <= p.y &&
         p.y <= std::max(a.y, b.y);
}

bool on_segment(Vec2 a, Vec2 b, Vec2 p) { return in_box(a, b, p) && orient2d(a, b, p) == 0; }

}  // namespace

bool on_any_segment(const std::vector<Segment>& segments, Vec2 p) {
  return std::any_of(segments.begin(), segments.end(), [p](const Segment& s) { return on_segment(s.a, s.b, p); });
}

namespace {

// A point shared legitimately by two segments (a vertex between consecutive segments of one curve,
// or a joint between two curve ends), with each segment's other end point.
struct SharedEnd {
  Vec2 at, u, v;
};

struct Conflict {
  int s = -1, t = -1;
  Vec2 near;
};

class IntersectionCheck {
 public:
  IntersectionCheck(const Geometry& g, const PointLines& lines) : g_(g), lines_(lines) {}

  void run() {
    const auto& segs = g_.segments;
    const int n = static_cast<int>(segs.size());
    const Box box = g_.extents;
    const double w = box.width(), h = box.height();
    // About one segment per cell; the second term keeps cells sane for a degenerate (flat) box.
    cell_ = std::max(std::sqrt(w * h / n), std::max(w, h) / n);
    nx_ = std::clamp(static_cast<int>(std::ceil(w / cell_)), 1, 4 * n + 1);
    ny_ = std::clamp(static_cast<int>(std::ceil(h / cell_)), 1, 4 * n + 1);
    std::vector<std::vector<int>> cells(static_cast<std::size_t>(nx_) * ny_);
    for (int s = 0; s < n; ++s) {
      const auto [x0, y0] = cell_of(lo(segs[s]));
      const auto [x1, y1] = cell_of(hi(segs[s]));
      for (int iy = y0; iy <= y1; ++iy)
        for (int ix = x0; ix <= x1; ++ix) cells[static_cast<std::size_t>(iy) * nx_ + ix].push_back(s);
    }
    for (int iy = 0; iy < ny_; ++iy) {
      for (int ix = 0; ix < nx_; ++ix) {
        const auto& list = cells[static_cast<std::size_t>(iy) * nx_ + ix];
        for (std::size_t i = 0; i < list.size(); ++i)
          for (std::size_t j = i + 1; j < list.size(); ++j) test_pair(list[i], list[j], ix, iy);
      }
    }
    if (worst_.s >= 0) report();
  }

 private:
  static Vec2 lo(const Segment& s) { return {std::min(s.a.x, s.b.x), std::min(s.a.y, s.b.y)}; }
  static Vec2 hi(const Segment& s) { return {std::max(s.a.x, s.b.x), std::max(s.a.y, s.b.y)}; }

  std::pair<int, int> cell_of(Vec2 p) const {
    const int ix = static_cast<int>(std::floor((p.x - g_.extents.lo.x) / cell_));
    const int iy = static_cast<int>(std::floor((p.y - g_.extents.lo.y) / cell_));
    return {std::clamp(ix, 0, nx_ - 1), std::clamp(iy, 0, ny_ - 1)};
  }

  bool is_curve_start(const Segment& s) const { return s.index == 0; }
  bool is_curve_end(const Segment& s) const { return s.index == g_.curves[s.curve].segment_count() - 1; }

  // Legitimately shared points of segments s and t (at most four).
  int shared_ends(const Segment& s, const Segment& t, SharedEnd out[4]) const {
    int count = 0;
    const bool same_curve = s.curve == t.curve;
    auto add = [&](Vec2 at, Vec2 u, Vec2 v) { out[count++] = {at, u, v}; };
    // Consecutive segments of one curve share their common vertex.
    if (same_curve && t.index == s.index + 1) add(s.b, s.a, t.b);
    if (same_curve && s.index == t.index + 1) add(s.a, s.b, t.a);
    // Curve ends at a joint (this includes the closing point of a closed curve). After snapping,
    // ends at one joint have identical coordinates and ends at different joints differ.
    // A constraint shares any vertex with another curve: build_geometry made each meeting point a
    // vertex of both.
    const bool meeting = !same_curve && (g_.curves[s.curve].constraint || g_.curves[t.curve].constraint);
    const bool s_ends[2] = {meeting || is_curve_start(s), meeting || is_curve_end(s)};
    const bool t_ends[2] = {meeting || is_curve_start(t), meeting || is_curve_end(t)};
    for (int es = 0; es < 2; ++es) {
      for (int et = 0; et < 2; ++et) {
        if (!s_ends[es] || !t_ends[et]) continue;
        const Vec2 ps = es == 0 ? s.a : s.b;
        const Vec2 pt = et == 0 ? t.a : t.b;
        if (!(ps == pt)) continue;
        add(ps, es == 0 ? s.b : s.a, et == 0 ? t.b : t.a);
      }
    }
    return count;
  }

  void test_pair(int s, int t, int ix, int iy) {
    if (s > t) std::swap(s, t);
    const Segment& a = g_.segments[s];
    const Segment& b = g_.segments[t];
    const Vec2 alo = lo(a), ahi = hi(a), blo = lo(b), bhi = hi(b);
    if (alo.x > bhi.x || blo.x > ahi.x || alo.y > bhi.y || blo.y > ahi.y) return;
    // Test each pair once: in the cell holding the low corner of the boxes' overlap.
    if (cell_of({std::max(alo.x, blo.x), std::max(alo.y, blo.y)}) != std::pair{ix, iy}) return;
    if (worst_.s >= 0 && std::pair{s, t} >= std::pair{worst_.s, worst_.t}) return;

    SharedEnd shared[4];
    const int count = shared_ends(a, b, shared);
    std::optional<Vec2> near;
    if (count == 0) {
      if (segments_intersect(a.a, a.b, b.a, b.b)) near = meeting_point(a, b);
    } else {
      // Sharing a point, the two segments meet elsewhere only if they are collinear and run the
      // same way from it (one folds back over the other).
      for (int i = 0; i < count && !near; ++i) {
        const SharedEnd& e = shared[i];
        if (orient2d(e.at, e.u, e.v) == 0 && dot(e.u - e.at, e.v - e.at) > 0) near = e.at;
      }
    }
    if (near) worst_ = {s, t, *near};
  }

  // An approximate meeting point of two intersecting segments, for the message only.
  static Vec2 meeting_point(const Segment& s, const Segment& t) {
    const Vec2 r = s.b - s.a, q = t.b - t.a;
    const double den = cross(r, q);
    if (den != 0) return s.a + (cross(t.a - s.a, q) / den) * r;
    for (const Vec2 p : {t.a, t.b, s.a, s.b})
      if (on_segment(s.a, s.b, p) && on_segment(t.a, t.b, p)) return p;
    return s.a;
  }

  std::string describe(int s) const {
    const Segment& seg = g_.segments[s];
    const Curve& c = g_.curves[seg.curve];
    return fmt::format("segment {} ({})", seg.index, where(c.file, lines_[seg.curve][seg.index]));
  }

  [[noreturn]] void report() const {
    const Segment& s = g_.segments[worst_.s];
    const Segment& t = g_.segments[worst_.t];
    const std::string near = format_point(worst_.near);
    if (s.curve == t.curve) {
      throw GeometryError(fmt::format("curve '{}' intersects itself: {} and {} meet near {}", g_.curves[s.curve].name,
                                      describe(worst_.s), describe(worst_.t), near));
    }
    throw GeometryError(fmt::format("curves intersect: curve '{}' {} and curve '{}' {} meet near {}",
                                    g_.curves[s.curve].name, describe(worst_.s), g_.curves[t.curve].name,
                                    describe(worst_.t), near));
  }

  const Geometry& g_;
  const PointLines& lines_;
  double cell_ = 1.0;
  int nx_ = 1, ny_ = 1;
  Conflict worst_;
};

}  // namespace

void check_intersections(const Geometry& geometry, const PointLines& lines) {
  if (geometry.segments.size() < 2) return;
  IntersectionCheck(geometry, lines).run();
}

}  // namespace pdmesh::detail
