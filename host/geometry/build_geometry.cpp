// build_geometry(): validates raw curves, snaps curve ends into joints, chains curves into loops and
// derives segments, arc lengths, critical points, loop areas, nesting depths and the domain area.
#include <algorithm>
#include <string>
#include <array>
#include <cmath>
#include <map>
#include <numbers>
#include <utility>

#include <fmt/format.h>

#include "core/errors.hpp"
#include "geometry/geometry.hpp"
#include "geometry/geometry_detail.hpp"

namespace pdmesh {
namespace {

using detail::format_point;
using detail::PointLines;
using detail::where;

// One end of a curve: end 0 is its first point, end 1 its last.
struct CurveEnd {
  int curve = 0;
  int end = 0;
};

int end_point_index(const Curve& c, int end) { return end == 0 ? 0 : static_cast<int>(c.points.size()) - 1; }

// Names, point counts and finite coordinates; fills the per-point source lines.
void check_points(std::vector<RawCurve>& raw, PointLines& lines) {
  lines.resize(raw.size());
  for (std::size_t k = 0; k < raw.size(); ++k) {
    RawCurve& r = raw[k];
    if (r.name.empty()) r.name = fmt::format("curve{}", k);
    auto& ln = lines[k];
    if (r.lines.size() == r.points.size()) {
      ln = r.lines;
    } else {
      ln.resize(r.points.size());
      for (std::size_t i = 0; i < ln.size(); ++i) ln[i] = r.line + static_cast<int>(i);
    }
    if (r.points.size() < 2) {
      throw GeometryError(fmt::format("{}: curve '{}' has {} point{}; a curve needs at least 2", where(r.file, r.line),
                                      r.name, r.points.size(), r.points.size() == 1 ? "" : "s"));
    }
    for (std::size_t i = 0; i < r.points.size(); ++i) {
      const Vec2 p = r.points[i];
      if (!std::isfinite(p.x) || !std::isfinite(p.y)) {
        throw GeometryError(fmt::format("{}: curve '{}' point {} has a non-finite coordinate ({}, {})",
                                        where(r.file, ln[i]), r.name, i, p.x, p.y));
      }
    }
  }
}

// Snaps every curve end to the first end seen within `tolerance`; returns the joint id of each end
// (ends[c][e]) and the joint locations. Exactly equal ends always join, even with zero tolerance.
std::vector<Vec2> snap_ends(std::vector<Curve>& curves, double tolerance, std::vector<std::array<int, 2>>& ends) {
  std::vector<Vec2> joints;
  std::multimap<double, int> by_x;  // joint ids keyed by x, for a range query around each end
  ends.assign(curves.size(), std::array<int, 2>{-1, -1});
  for (std::size_t c = 0; c < curves.size(); ++c) {
    for (int e = 0; e < 2; ++e) {
      Vec2& p = curves[c].points[end_point_index(curves[c], e)];
      int best = -1;
      double best_d = 0.0;
      for (auto it = by_x.lower_bound(p.x - tolerance); it != by_x.end() && it->first <= p.x + tolerance; ++it) {
        const double d = dist(p, joints[it->second]);
        if (d <= tolerance && (best < 0 || d < best_d)) {
          best = it->second;
          best_d = d;
        }
      }
      if (best < 0) {
        best = static_cast<int>(joints.size());
        joints.push_back(p);
        by_x.emplace(p.x, best);
      }
      p = joints[best];
      ends[c][e] = best;
    }
  }
  return joints;
}

void check_zero_length(const std::vector<Curve>& curves, const PointLines& lines) {
  for (std::size_t c = 0; c < curves.size(); ++c) {
    const auto& pts = curves[c].points;
    for (std::size_t k = 0; k + 1 < pts.size(); ++k) {
      if (pts[k] == pts[k + 1]) {
        throw GeometryError(
            fmt::format("{}: curve '{}' segment {} has zero length: points {} and {} are both {} (repeated point{})",
                        where(curves[c].file, lines[c][k + 1]), curves[c].name, k, k, k + 1, format_point(pts[k]),
                        pts.size() == 2 ? ", or curve ends closer than the join tolerance" : ""));
      }
    }
  }
}

// Every joint must hold exactly two curve ends.
std::vector<std::vector<CurveEnd>> check_joints(const std::vector<Curve>& curves, const PointLines& lines,
                                                const std::vector<Vec2>& joints,
                                                const std::vector<std::array<int, 2>>& ends) {
  std::vector<std::vector<CurveEnd>> at(joints.size());
  for (std::size_t c = 0; c < curves.size(); ++c)
    for (int e = 0; e < 2; ++e) at[ends[c][e]].push_back({static_cast<int>(c), e});
  auto end_where = [&](CurveEnd ce) {
    return where(curves[ce.curve].file, lines[ce.curve][end_point_index(curves[ce.curve], ce.end)]);
  };
  for (std::size_t j = 0; j < joints.size(); ++j) {
    // Embedded constraints end anywhere: the rule is the boundary curves' (their ends are dropped
    // from the list the loops are chained by; find_critical_points gets them all).
    std::vector<CurveEnd>& here = at[j];
    here.erase(std::remove_if(here.begin(), here.end(), [&](CurveEnd ce) { return curves[ce.curve].constraint; }),
               here.end());
    if (at[j].size() == 1) {
      const CurveEnd ce = at[j][0];
      throw GeometryError(fmt::format("loop does not close: {} of curve '{}' ({}) at {} meets no other curve",
                                      ce.end == 0 ? "start" : "end", curves[ce.curve].name, end_where(ce),
                                      format_point(joints[j])));
    }
    if (at[j].size() > 2) {
      std::string list;
      for (const CurveEnd ce : at[j]) {
        if (!list.empty()) list += ", ";
        list +=
            fmt::format("{} of curve '{}' ({})", ce.end == 0 ? "start" : "end", curves[ce.curve].name, end_where(ce));
      }
      throw GeometryError(fmt::format("{} curve ends meet at {}: {}; exactly two curve ends may meet at a joint",
                                      at[j].size(), format_point(joints[j]), list));
    }
  }
  return at;
}

// Chains curves into loops; each joint joins exactly two ends, so the curves form disjoint cycles.
std::vector<Loop> chain_loops(const std::vector<Curve>& curves, const std::vector<std::array<int, 2>>& ends,
                              const std::vector<std::vector<CurveEnd>>& at) {
  std::vector<Loop> loops;
  std::vector<std::uint8_t> used(curves.size(), 0);
  for (std::size_t c = 0; c < curves.size(); ++c) used[c] = curves[c].constraint ? 1 : 0;
  for (int c0 = 0; c0 < static_cast<int>(curves.size()); ++c0) {
    if (used[c0]) continue;
    Loop loop;
    int c = c0;
    bool reversed = false;
    while (true) {
      loop.curves.push_back(c);
      loop.reversed.push_back(reversed ? 1 : 0);
      used[c] = 1;
      const int exit_end = reversed ? 0 : 1;
      const auto& pair = at[ends[c][exit_end]];
      const CurveEnd next = (pair[0].curve == c && pair[0].end == exit_end) ? pair[1] : pair[0];
      if (next.curve == c0) break;
      c = next.curve;
      reversed = next.end == 1;
    }
    loops.push_back(std::move(loop));
  }
  return loops;
}

// Shoelace formula relative to the loop's first vertex, which keeps the sum accurate far from 0.
double signed_area(const std::vector<Curve>& curves, const Loop& loop) {
  const Vec2 ref = curves[loop.curves[0]].points[0];
  double twice = 0.0;
  for (std::size_t i = 0; i < loop.curves.size(); ++i) {
    const auto& pts = curves[loop.curves[i]].points;
    double sum = 0.0;
    for (std::size_t k = 0; k + 1 < pts.size(); ++k) sum += cross(pts[k] - ref, pts[k + 1] - ref);
    twice += loop.reversed[i] ? -sum : sum;
  }
  return 0.5 * twice;
}

// A loop must enclose an area that doubles can tell from zero and a mesh could fill. Its mean width
// w = 2|A| / P (area over half the perimeter: about h for a strip of width h) must be at least the
// larger of
//  - the spacing of doubles at its largest coordinate M (M 2^-52): below it the loop cannot be told
//    from a doubled-back line, and
//  - P / 2^31: a mesh must put nodes along the loop at most w apart to fit one inside it, and more
//    than 2^31 nodes cannot be indexed.
// 2|A| is the shoelace sum less its rounding bound (n + 4) 2^-53 sum |terms| (n terms), so only an
// area known to be large enough passes. The thesis' geometries have widths some ten orders of magnitude above.
void check_loop_area(const Geometry& g, const Loop& loop, const PointLines& lines) {
  const Vec2 ref = g.curves[loop.curves[0]].points[0];
  double twice = 0.0, magnitude = 0.0, perimeter = 0.0, largest = 0.0;
  std::size_t terms = 0;
  for (std::size_t i = 0; i < loop.curves.size(); ++i) {
    const Curve& curve = g.curves[loop.curves[i]];
    const auto& pts = curve.points;
    double sum = 0.0;
    for (std::size_t k = 0; k + 1 < pts.size(); ++k) {
      const Vec2 a = pts[k] - ref, b = pts[k + 1] - ref;
      sum += cross(a, b);
      magnitude += std::fabs(a.x * b.y) + std::fabs(a.y * b.x);
      ++terms;
    }
    for (const Vec2 p : pts) largest = std::max({largest, std::fabs(p.x), std::fabs(p.y)});
    twice += loop.reversed[i] ? -sum : sum;
    perimeter += curve.arc.back();
  }
  const double rounding = static_cast<double>(terms + 4) * std::ldexp(magnitude, -53);
  const double width = std::max(0.0, std::fabs(twice) - rounding) / perimeter;
  const double quantum = std::ldexp(largest, -52);
  const double finest = std::ldexp(perimeter, -31);
  if (width >= quantum && width >= finest) return;
  const Curve& first = g.curves[loop.curves[0]];
  const std::string curves = loop.curves.size() == 1
                                 ? fmt::format("curve '{}'", first.name)
                                 : fmt::format("curve '{}' and {} more curve{}", first.name, loop.curves.size() - 1,
                                               loop.curves.size() == 2 ? "" : "s");
  throw GeometryError(fmt::format(
      "{}: the loop of {} encloses almost no area: area {:.3g} over its perimeter {:.6g} is a mean width of {:.3g}, "
      "below {:.3g} ({}); a loop needs an inside (is it a line traced out and back?)",
      where(first.file, lines[loop.curves[0]].empty() ? first.line : lines[loop.curves[0]][0]), curves,
      0.5 * std::fabs(twice), perimeter, width, std::max(quantum, finest),
      quantum >= finest ? fmt::format("the spacing of doubles at its coordinates, which reach {:.6g}", largest)
                        : "its perimeter / 2^31: a mesh would need more nodes along it than it can index"));
}

// Joints, then sharp interior corners, in curve order; one entry per distinct location.
void find_critical_points(Geometry& g, const std::vector<Vec2>& joints, const std::vector<std::array<int, 2>>& ends,
                          const std::vector<std::vector<CurveEnd>>& at, double corner_angle_deg) {
  std::vector<int> joint_entry(joints.size(), -1);
  const double limit = corner_angle_deg * std::numbers::pi / 180.0;
  for (int c = 0; c < static_cast<int>(g.curves.size()); ++c) {
    Curve& curve = g.curves[c];
    const int n = static_cast<int>(curve.points.size());
    curve.critical.assign(n, 0);
    for (int k = 0; k < n; ++k) {
      if (k == 0 || k == n - 1) {
        curve.critical[k] = 1;
        const int j = ends[c][k == 0 ? 0 : 1];
        if (joint_entry[j] >= 0) continue;
        joint_entry[j] = static_cast<int>(g.critical.size());
        CriticalPoint cp{joints[j], {}, {}};
        for (const CurveEnd ce : at[j]) {
          cp.curves.push_back(ce.curve);
          cp.indices.push_back(end_point_index(g.curves[ce.curve], ce.end));
        }
        g.critical.push_back(std::move(cp));
        continue;
      }
      const double turn =
          detail::turning_angle(curve.points[k] - curve.points[k - 1], curve.points[k + 1] - curve.points[k]);
      if (turn > limit || curve.fixed_points) {
        curve.critical[k] = 1;
        g.critical.push_back({curve.points[k], {c}, {k}});
      }
    }
  }
}

// With embedded constraints: a point is critical when it is a curve end, a sharp corner, a point of a
// fixed_points curve or a meeting point (`forced`); the critical points at one location are one
// entry (curves meet there with identical coordinates), in order of first appearance.
void find_grouped_critical_points(Geometry& g, const std::vector<std::vector<std::uint8_t>>& forced,
                                  double corner_angle_deg) {
  const double limit = corner_angle_deg * std::numbers::pi / 180.0;
  std::map<std::pair<double, double>, int> entry;
  for (int c = 0; c < static_cast<int>(g.curves.size()); ++c) {
    Curve& curve = g.curves[c];
    const int n = static_cast<int>(curve.points.size());
    curve.critical.assign(n, 0);
    for (int k = 0; k < n; ++k) {
      // Every input vertex of a constraint is kept (a node of the mesh), like a critical point.
      bool critical = k == 0 || k == n - 1 || curve.fixed_points || curve.constraint || forced[c][k];
      if (!critical) {
        critical =
            detail::turning_angle(curve.points[k] - curve.points[k - 1], curve.points[k + 1] - curve.points[k]) > limit;
      }
      if (!critical) continue;
      curve.critical[k] = 1;
      const Vec2 p = curve.points[k];
      const auto [it, fresh] = entry.emplace(std::pair{p.x, p.y}, static_cast<int>(g.critical.size()));
      if (fresh) g.critical.push_back({p, {}, {}});
      CriticalPoint& cp = g.critical[static_cast<std::size_t>(it->second)];
      cp.curves.push_back(c);
      cp.indices.push_back(k);
    }
  }
}

void fill_segments(Geometry& g) {
  for (int c = 0; c < static_cast<int>(g.curves.size()); ++c) {
    Curve& curve = g.curves[c];
    curve.first_segment = static_cast<int>(g.segments.size());
    curve.arc.assign(curve.points.size(), 0.0);
    for (int k = 0; k + 1 < static_cast<int>(curve.points.size()); ++k) {
      const double len = dist(curve.points[k], curve.points[k + 1]);
      curve.arc[k + 1] = curve.arc[k] + len;
      g.segments.push_back({curve.points[k], curve.points[k + 1], c, k, len});
    }
  }
}

// Depth of each loop = number of other loops containing its first vertex. Loops do not intersect
// (checked before), so one vertex decides and it lies on no other loop.
void find_depths(Geometry& g) {
  std::vector<std::vector<int>> loop_segments(g.loops.size());
  std::vector<Box> boxes(g.loops.size());
  for (std::size_t l = 0; l < g.loops.size(); ++l) {
    for (const int c : g.loops[l].curves) {
      const Curve& curve = g.curves[c];
      for (int k = 0; k < curve.segment_count(); ++k) loop_segments[l].push_back(curve.first_segment + k);
      for (const Vec2 p : curve.points) boxes[l].add(p);
    }
  }
  for (std::size_t i = 0; i < g.loops.size(); ++i) {
    const Vec2 p = g.curves[g.loops[i].curves[0]].points[0];
    int depth = 0;
    for (std::size_t j = 0; j < g.loops.size(); ++j) {
      if (j == i || !boxes[j].contains(p)) continue;
      if (detail::ray_crossings(g.segments, loop_segments[j], p) % 2 == 1) ++depth;
    }
    g.loops[i].depth = depth;
  }
}

// The segments of the boundary curves (the embedded constraints' left out).
std::vector<int> wall_segments(const Geometry& g) {
  std::vector<int> ids;
  ids.reserve(g.segments.size());
  for (std::size_t s = 0; s < g.segments.size(); ++s)
    if (!g.curves[static_cast<std::size_t>(g.segments[s].curve)].constraint) ids.push_back(static_cast<int>(s));
  return ids;
}

void check_holes(Geometry& g, const std::vector<RawHolePoint>& holes) {
  const std::vector<int> all = wall_segments(g);
  std::vector<Segment> walls;
  for (const int s : all) walls.push_back(g.segments[static_cast<std::size_t>(s)]);
  for (const RawHolePoint& h : holes) {
    if (!std::isfinite(h.p.x) || !std::isfinite(h.p.y)) {
      throw GeometryError(
          fmt::format("{}: hole point ({}, {}) has a non-finite coordinate", where(h.file, h.line), h.p.x, h.p.y));
    }
    if (detail::on_any_segment(walls, h.p)) {
      throw GeometryError(fmt::format("{}: hole point {} lies on the boundary; it must lie inside a hole",
                                      where(h.file, h.line), format_point(h.p)));
    }
    if (detail::ray_crossings(g.segments, all, h.p) % 2 == 1) {
      throw GeometryError(
          fmt::format("{}: hole point {} lies inside the domain, not in a hole (the domain is the even-odd interior "
                      "of the loops)",
                      where(h.file, h.line), format_point(h.p)));
    }
    g.hole_points.push_back(h);
  }
}

// Every embedded constraint lies inside the domain: the pieces between its meeting points touch the
// boundary curves only at their ends, so a point of each piece off the boundary decides it.
void check_constraints_inside(const Geometry& g, const std::vector<int>& walls_ids, const PointLines& lines) {
  std::vector<Segment> walls;
  for (const int s : walls_ids) walls.push_back(g.segments[static_cast<std::size_t>(s)]);
  auto outside = [&](Vec2 p) {
    return !detail::on_any_segment(walls, p) && detail::ray_crossings(g.segments, walls_ids, p) % 2 == 0;
  };
  for (const Segment& s : g.segments) {
    const Curve& c = g.curves[static_cast<std::size_t>(s.curve)];
    if (!c.constraint) continue;
    const Vec2 mid = 0.5 * (s.a + s.b);
    if (!outside(mid)) continue;
    // Name an input point of the piece when one is off the boundary, else its midpoint.
    Vec2 at = mid;
    int line = lines[static_cast<std::size_t>(s.curve)][static_cast<std::size_t>(s.index)];
    if (!detail::on_any_segment(walls, s.a)) {
      at = s.a;
    } else if (!detail::on_any_segment(walls, s.b)) {
      at = s.b;
      line = lines[static_cast<std::size_t>(s.curve)][static_cast<std::size_t>(s.index) + 1];
    }
    throw GeometryError(fmt::format(
        "{}: constraint curve '{}' leaves the domain: its point {} (segment {}) lies outside it, in a hole or "
        "outside every loop; an embedded constraint must lie inside the domain",
        where(c.file, line), c.name, format_point(at), s.index));
  }
}

void check_points_inside(Geometry& g, const std::vector<int>& walls_ids, const std::vector<RawPoint>& points) {
  for (const RawPoint& rp : points) {
    if (detail::ray_crossings(g.segments, walls_ids, rp.p) % 2 == 0) {
      throw GeometryError(fmt::format(
          "{}: point {} lies outside the domain, in a hole or outside every loop; an embedded point must lie "
          "inside the domain",
          where(rp.file, rp.line), format_point(rp.p)));
    }
    g.embedded_points.push_back(rp);
  }
}

void check_options(const GeometryOptions& options) {
  if (!std::isfinite(options.join_tolerance) || options.join_tolerance < 0 || options.join_tolerance >= 1) {
    throw GeometryError(fmt::format("join tolerance {} must be >= 0 and < 1", options.join_tolerance));
  }
  if (!std::isfinite(options.corner_angle_deg) || options.corner_angle_deg < 0 || options.corner_angle_deg > 180) {
    throw GeometryError(fmt::format("corner angle {} degrees must be in [0, 180]", options.corner_angle_deg));
  }
}

Curve make_curve(RawCurve& r) {
  Curve c;
  c.name = std::move(r.name);
  c.points = std::move(r.points);
  c.file = std::move(r.file);
  c.line = r.line;
  c.fixed_points = r.fixed_points;
  c.constraint = r.constraint;
  return c;
}

void finish_loops(Geometry& g, const PointLines& lines) {
  for (Loop& loop : g.loops) {
    loop.signed_area = signed_area(g.curves, loop);
    check_loop_area(g, loop, lines);
  }
  find_depths(g);
  g.area = 0.0;
  for (const Loop& loop : g.loops) g.area += std::fabs(loop.signed_area) * (loop.depth % 2 == 0 ? 1.0 : -1.0);
}

}  // namespace

Geometry build_geometry(RawGeometry raw, const GeometryOptions& options) {
  const bool embedded = !raw.points.empty() || std::any_of(raw.curves.begin(), raw.curves.end(),
                                                           [](const RawCurve& c) { return c.constraint; });
  if (!embedded) return build_geometry(std::move(raw.curves), raw.holes, options);
  if (std::all_of(raw.curves.begin(), raw.curves.end(), [](const RawCurve& c) { return c.constraint; })) {
    const std::string first =
        raw.curves.empty() ? std::string("point input") : where(raw.curves[0].file, raw.curves[0].line);
    throw GeometryError(fmt::format(
        "{}: the geometry has embedded constraints or points but no boundary curve; they need a domain to lie in",
        raw.curves.empty() && !raw.points.empty() ? where(raw.points[0].file, raw.points[0].line) : first));
  }
  check_options(options);
  PointLines lines;
  check_points(raw.curves, lines);

  Geometry g;
  g.curves.reserve(raw.curves.size());
  for (RawCurve& r : raw.curves) {
    g.curves.push_back(make_curve(r));
    for (const Vec2 p : g.curves.back().points) g.extents.add(p);
  }
  const double tolerance = options.join_tolerance * g.extents.diagonal();
  detail::snap_constraint_ends(g.curves, tolerance);
  std::vector<std::array<int, 2>> ends;
  const std::vector<Vec2> joints = snap_ends(g.curves, tolerance, ends);
  check_zero_length(g.curves, lines);
  std::vector<RawPoint> free_points;
  const auto forced = detail::split_at_constraints(g.curves, lines, raw.points, tolerance, free_points);
  const auto at = check_joints(g.curves, lines, joints, ends);
  g.loops = chain_loops(g.curves, ends, at);
  find_grouped_critical_points(g, forced, options.corner_angle_deg);
  fill_segments(g);
  detail::check_intersections(g, lines);
  finish_loops(g, lines);
  check_holes(g, raw.holes);
  const std::vector<int> walls = wall_segments(g);
  check_constraints_inside(g, walls, lines);
  check_points_inside(g, walls, free_points);
  return g;
}

Geometry build_geometry(std::vector<RawCurve> raw, const GeometryOptions& options) {
  return build_geometry(std::move(raw), {}, options);
}

Geometry build_geometry(std::vector<RawCurve> raw, const std::vector<RawHolePoint>& holes,
                        const GeometryOptions& options) {
  if (raw.empty()) throw GeometryError("the geometry has no curves");
  if (std::any_of(raw.begin(), raw.end(), [](const RawCurve& c) { return c.constraint; }))
    return build_geometry(RawGeometry{std::move(raw), holes, {}, {}, {}, {}}, options);
  check_options(options);
  PointLines lines;
  check_points(raw, lines);

  Geometry g;
  g.curves.reserve(raw.size());
  for (RawCurve& r : raw) {
    g.curves.push_back(make_curve(r));
    for (const Vec2 p : g.curves.back().points) g.extents.add(p);
  }

  std::vector<std::array<int, 2>> ends;
  const std::vector<Vec2> joints = snap_ends(g.curves, options.join_tolerance * g.extents.diagonal(), ends);
  check_zero_length(g.curves, lines);
  const auto at = check_joints(g.curves, lines, joints, ends);
  g.loops = chain_loops(g.curves, ends, at);
  find_critical_points(g, joints, ends, at, options.corner_angle_deg);
  fill_segments(g);
  detail::check_intersections(g, lines);

  finish_loops(g, lines);
  check_holes(g, holes);
  return g;
}

}  // namespace pdmesh
