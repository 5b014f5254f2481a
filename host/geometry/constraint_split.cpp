// Embedded constraints in build_geometry: where constraint curves meet each other or a boundary
// curve (a crossing, a T-junction, an end on a curve), the meeting point becomes a vertex of both
// curves and a critical point; embedded points within the join tolerance of a curve are put on it.
// See docs/geometry-input.md, "Embedded constraints".
#include <algorithm>
#include <cmath>
#include <set>
#include <utility>

#include <fmt/format.h>

#include "core/errors.hpp"
#include "core/predicates.hpp"
#include "geometry/geometry_detail.hpp"

namespace pdmesh::detail {
namespace {

// A point to insert into segment `segment` of a curve, at parameter t along it.
struct Insertion {
  int segment = 0;
  double t = 0.0;
  Vec2 p;
};

struct SegmentRef {
  int curve = 0, index = 0;
  Vec2 a, b;
};

double param_on(Vec2 a, Vec2 b, Vec2 p) {
  const Vec2 d = b - a;
  return std::clamp(dot(p - a, d) / norm2(d), 0.0, 1.0);
}

Vec2 closest_point(Vec2 a, Vec2 b, Vec2 p) { return a + param_on(a, b, p) * (b - a); }

bool boxes_meet(const SegmentRef& s, const SegmentRef& t, double slack) {
  return std::min(s.a.x, s.b.x) - slack <= std::max(t.a.x, t.b.x) &&
         std::min(t.a.x, t.b.x) - slack <= std::max(s.a.x, s.b.x) &&
         std::min(s.a.y, s.b.y) - slack <= std::max(t.a.y, t.b.y) &&
         std::min(t.a.y, t.b.y) - slack <= std::max(s.a.y, s.b.y);
}

class Splitter {
 public:
  Splitter(std::vector<Curve>& curves, PointLines& lines, double tolerance)
      : curves_(curves), lines_(lines), tolerance_(tolerance), inserts_(curves.size()), marks_(curves.size()) {}

  // Constraint ends within the tolerance of another curve's vertex move onto it (before the ends are
  // snapped into joints, so that ends moved onto one vertex join).
  void snap_ends_to_vertices() {
    // Every vertex by x (and its curve), for a range query around each end.
    std::vector<std::pair<Vec2, std::size_t>> by_x;
    for (std::size_t c = 0; c < curves_.size(); ++c)
      for (const Vec2 v : curves_[c].points) by_x.push_back({v, c});
    std::sort(by_x.begin(), by_x.end(), [](const auto& u, const auto& w) { return u.first.x < w.first.x; });
    for (std::size_t c = 0; c < curves_.size(); ++c) {
      Curve& curve = curves_[c];
      if (!curve.constraint) continue;
      for (const std::size_t k : {std::size_t{0}, curve.points.size() - 1}) {
        Vec2& e = curve.points[k];
        double best = tolerance_;
        Vec2 to = e;
        auto it = std::lower_bound(by_x.begin(), by_x.end(), e.x - tolerance_,
                                   [](const auto& u, double x) { return u.first.x < x; });
        for (; it != by_x.end() && it->first.x <= e.x + tolerance_; ++it) {
          if (it->second == c) continue;
          const double dd = dist(e, it->first);
          if (dd > 0.0 && dd <= best) {
            best = dd;
            to = it->first;
          }
        }
        e = to;
      }
    }
  }

  // Finds every meeting of a constraint segment with a segment of another curve (or of a boundary
  // with a constraint) and records the insertions and critical marks.
  void find_meetings() {
    std::vector<SegmentRef> all;
    for (std::size_t c = 0; c < curves_.size(); ++c) {
      const auto& pts = curves_[c].points;
      for (std::size_t k = 0; k + 1 < pts.size(); ++k)
        all.push_back({static_cast<int>(c), static_cast<int>(k), pts[k], pts[k + 1]});
    }
    // Sorted by the low x of their boxes: each constraint segment scans only those that can reach it,
    // from the first whose low x is within the widest box's width (and the tolerance) of its own.
    std::sort(all.begin(), all.end(),
              [](const SegmentRef& s, const SegmentRef& t) { return std::min(s.a.x, s.b.x) < std::min(t.a.x, t.b.x); });
    double widest = 0.0;
    for (const SegmentRef& t : all) widest = std::max(widest, std::fabs(t.b.x - t.a.x));
    for (std::size_t i = 0; i < all.size(); ++i) {
      const SegmentRef& s = all[i];
      if (!curves_[s.curve].constraint) continue;
      const double hi_x = std::max(s.a.x, s.b.x) + tolerance_;
      const double from_x = std::min(s.a.x, s.b.x) - tolerance_ - widest;
      const auto first = std::lower_bound(all.begin(), all.end(), from_x,
                                          [](const SegmentRef& t, double x) { return std::min(t.a.x, t.b.x) < x; });
      // Segments before i whose box reaches s were scanned when they were s (if constraints) or are
      // scanned here (boundaries): go back over the boundaries among them.
      for (auto j = static_cast<std::size_t>(first - all.begin()); j < all.size(); ++j) {
        const SegmentRef& t = all[j];
        if (j > i && std::min(t.a.x, t.b.x) > hi_x) break;
        if (j == i || t.curve == s.curve) continue;
        if (j < i && curves_[t.curve].constraint) continue;  // that pair was tested with t first
        if (!boxes_meet(s, t, tolerance_)) continue;
        meet(s, t);
      }
    }
  }

  // Embedded points within the tolerance of a curve go onto it (a critical vertex there); the
  // others are returned, duplicates within the tolerance merged.
  std::vector<RawPoint> place_points(const std::vector<RawPoint>& points) {
    std::vector<RawPoint> free;
    for (const RawPoint& rp : points) {
      if (!std::isfinite(rp.p.x) || !std::isfinite(rp.p.y))
        throw GeometryError(
            fmt::format("{}: point ({}, {}) has a non-finite coordinate", where(rp.file, rp.line), rp.p.x, rp.p.y));
      int best_c = -1, best_k = -1;
      double best = tolerance_;
      Vec2 at;
      for (std::size_t c = 0; c < curves_.size(); ++c) {
        const auto& pts = curves_[c].points;
        for (std::size_t k = 0; k + 1 < pts.size(); ++k) {
          const Vec2 q =
              point_on_segment_exact(pts[k], pts[k + 1], rp.p) ? rp.p : closest_point(pts[k], pts[k + 1], rp.p);
          const double d = dist(q, rp.p);
          if (d <= best && (best_c < 0 || d < best)) {
            best = d;
            best_c = static_cast<int>(c);
            best_k = static_cast<int>(k);
            at = q;
          }
        }
      }
      if (best_c >= 0) {
        const auto& pts = curves_[best_c].points;
        const Vec2 a = pts[best_k], b = pts[best_k + 1];
        // Onto the nearer end vertex when that is within the tolerance too, else into the segment.
        if (dist(a, rp.p) <= tolerance_ || dist(b, rp.p) <= tolerance_) {
          marks_[best_c].insert(key(dist(a, rp.p) <= dist(b, rp.p) ? a : b));
        } else {
          const Vec2 p = rp.p;  // the point itself: it lies within the tolerance of the segment
          add(best_c, best_k, a, b, p);
        }
        continue;
      }
      const bool duplicate =
          std::any_of(free.begin(), free.end(), [&](const RawPoint& f) { return dist(f.p, rp.p) <= tolerance_; });
      if (!duplicate) free.push_back(rp);
    }
    return free;
  }

  // Inserts the recorded points and returns, per curve and point, whether it must be critical.
  std::vector<std::vector<std::uint8_t>> apply() {
    std::vector<std::vector<std::uint8_t>> forced(curves_.size());
    for (std::size_t c = 0; c < curves_.size(); ++c) {
      auto& ins = inserts_[c];
      std::sort(ins.begin(), ins.end(), [](const Insertion& x, const Insertion& y) {
        return x.segment != y.segment ? x.segment < y.segment : x.t < y.t;
      });
      Curve& curve = curves_[c];
      std::vector<Vec2> pts;
      std::vector<int> ln;
      std::size_t next = 0;
      for (std::size_t k = 0; k < curve.points.size(); ++k) {
        pts.push_back(curve.points[k]);
        ln.push_back(lines_[c][k]);
        for (; next < ins.size() && ins[next].segment == static_cast<int>(k); ++next) {
          const Vec2 p = ins[next].p;
          if (p == pts.back() || p == curve.points[k + 1]) continue;
          pts.push_back(p);
          ln.push_back(lines_[c][k]);
        }
      }
      curve.points = std::move(pts);
      lines_[c] = std::move(ln);
      forced[c].assign(curve.points.size(), 0);
      for (std::size_t k = 0; k < curve.points.size(); ++k)
        if (marks_[c].count(key(curve.points[k]))) forced[c][k] = 1;
    }
    return forced;
  }

 private:
  using Key = std::pair<double, double>;
  static Key key(Vec2 p) { return {p.x, p.y}; }

  static bool point_on_segment_exact(Vec2 a, Vec2 b, Vec2 p) {
    return std::min(a.x, b.x) <= p.x && p.x <= std::max(a.x, b.x) && std::min(a.y, b.y) <= p.y &&
           p.y <= std::max(a.y, b.y) && orient2d(a, b, p) == 0.0;
  }

  // Records p as a critical vertex of curve c, inserted into its segment k (a, b) unless it is an end.
  void add(int c, int k, Vec2 a, Vec2 b, Vec2 p) {
    marks_[c].insert(key(p));
    if (p == a || p == b) return;
    inserts_[c].push_back({k, param_on(a, b, p), p});
  }

  std::string describe(const SegmentRef& s) const {
    const Curve& c = curves_[s.curve];
    return fmt::format("curve '{}' segment {} ({})", c.name, s.index, where(c.file, lines_[s.curve][s.index]));
  }

  void meet(const SegmentRef& s, const SegmentRef& t) {
    if (!segments_intersect(s.a, s.b, t.a, t.b)) {
      // Not touching exactly: a constraint end within the tolerance of the other segment joins it.
      const Curve& cs = curves_[s.curve];
      const bool s_first = s.index == 0, s_last = s.index + 2 == static_cast<int>(cs.points.size());
      for (const auto& [is_end, e] : {std::pair{s_first, s.a}, std::pair{s_last, s.b}}) {
        if (!is_end) continue;
        if (dist(closest_point(t.a, t.b, e), e) <= tolerance_) {
          marks_[s.curve].insert(key(e));
          add(t.curve, t.index, t.a, t.b, e);
        }
      }
      // And the other way round, when t belongs to a constraint.
      const Curve& ct = curves_[t.curve];
      if (ct.constraint) {
        const bool t_first = t.index == 0, t_last = t.index + 2 == static_cast<int>(ct.points.size());
        for (const auto& [is_end, e] : {std::pair{t_first, t.a}, std::pair{t_last, t.b}}) {
          if (!is_end) continue;
          if (dist(closest_point(s.a, s.b, e), e) <= tolerance_) {
            marks_[t.curve].insert(key(e));
            add(s.curve, s.index, s.a, s.b, e);
          }
        }
      }
      return;
    }
    const double o1 = orient2d(s.a, s.b, t.a), o2 = orient2d(s.a, s.b, t.b);
    Vec2 p;
    if (o1 == 0.0 && o2 == 0.0) {
      // Collinear: they may share one end point and run apart; anything more is an overlap.
      const Vec2 d = s.b - s.a;
      const double u0 = dot(t.a - s.a, d), u1 = dot(t.b - s.a, d), len = dot(d, d);
      const double lo = std::max(0.0, std::min(u0, u1)), hi = std::min(len, std::max(u0, u1));
      if (hi > lo)
        throw GeometryError(fmt::format("constraint overlaps a curve: {} and {} run along each other near {}",
                                        describe(s), describe(t), format_point(s.a + (lo / len) * d)));
      p = (t.a == s.a || t.a == s.b) ? t.a : t.b;
    } else if (o1 == 0.0) {
      p = t.a;
    } else if (o2 == 0.0) {
      p = t.b;
    } else if (orient2d(t.a, t.b, s.a) == 0.0) {
      p = s.a;
    } else if (orient2d(t.a, t.b, s.b) == 0.0) {
      p = s.b;
    } else {
      const Vec2 r = s.b - s.a, q = t.b - t.a;
      p = s.a + std::clamp(cross(t.a - s.a, q) / cross(r, q), 0.0, 1.0) * r;
      // On an axis-parallel segment the crossing keeps its constant coordinate exactly (roads and
      // grids cross so; the rounded point then lies on that segment).
      for (const SegmentRef* u : {&s, &t}) {
        if (u->a.x == u->b.x) p.x = u->a.x;
        if (u->a.y == u->b.y) p.y = u->a.y;
      }
      // A crossing within the tolerance of a vertex of either segment (a constraint's end that
      // rounding puts a hair beyond the other segment, a line drawn through a vertex) is at that
      // vertex, as an end that stops short joins the segment at the end itself: a point of its own
      // would leave a sliver segment beside the vertex.
      double nearest = tolerance_;
      Vec2 vertex = p;
      for (const Vec2 v : {s.a, s.b, t.a, t.b}) {
        const double d = dist(p, v);
        if (d <= nearest) {
          nearest = d;
          vertex = v;
        }
      }
      p = vertex;
    }
    add(s.curve, s.index, s.a, s.b, p);
    add(t.curve, t.index, t.a, t.b, p);
  }

  std::vector<Curve>& curves_;
  PointLines& lines_;
  double tolerance_;
  std::vector<std::vector<Insertion>> inserts_;
  std::vector<std::set<Key>> marks_;
};

}  // namespace

void snap_constraint_ends(std::vector<Curve>& curves, double tolerance) {
  PointLines unused;
  Splitter(curves, unused, tolerance).snap_ends_to_vertices();
}

std::vector<std::vector<std::uint8_t>> split_at_constraints(std::vector<Curve>& curves, PointLines& lines,
                                                            const std::vector<RawPoint>& points, double tolerance,
                                                            std::vector<RawPoint>& free_points) {
  Splitter splitter(curves, lines, tolerance);
  splitter.find_meetings();
  free_points = splitter.place_points(points);
  return splitter.apply();
}

}  // namespace pdmesh::detail
