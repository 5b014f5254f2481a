// Test helper: small Geometry values built directly (curves, segments, arc lengths, extents)
// without build_geometry, a few through it, plus a seeded, platform-independent random number source.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "geometry/geometry.hpp"
#include "seeded_random.hpp"
#include "spacing/spacing_field.hpp"

namespace pdmesh::fixtures {

// An input curve as a reader would return it, from the file "test".
inline RawCurve raw_polyline(std::vector<Vec2> points, const std::string& name) {
  RawCurve r;
  r.name = name;
  r.points = std::move(points);
  r.file = "test";
  return r;
}

// Fills curves (points, arc, critical = 0, first_segment), segments and extents from polylines.
// Loops and the area are left empty: the tree and spacing fields do not read them.
inline Geometry make_geometry(const std::vector<std::vector<Vec2>>& polylines) {
  Geometry g;
  for (std::size_t c = 0; c < polylines.size(); ++c) {
    Curve curve;
    curve.name = "curve" + std::to_string(c);
    curve.points = polylines[c];
    curve.critical.assign(curve.points.size(), 0);
    curve.first_segment = static_cast<int>(g.segments.size());
    curve.arc.push_back(0.0);
    for (std::size_t k = 0; k + 1 < curve.points.size(); ++k) {
      Segment s{curve.points[k], curve.points[k + 1], static_cast<int>(c), static_cast<int>(k), 0.0};
      s.length = dist(s.a, s.b);
      curve.arc.push_back(curve.arc.back() + s.length);
      g.segments.push_back(s);
    }
    for (const Vec2 p : curve.points) g.extents.add(p);
    g.curves.push_back(std::move(curve));
  }
  return g;
}

// Points on an arc of a circle, end points included; the ends are set exactly from `from`/`to`.
inline std::vector<Vec2> arc_points(Vec2 centre, double r, double a0, double a1, int segments, Vec2 from, Vec2 to) {
  std::vector<Vec2> pts;
  for (int i = 0; i <= segments; ++i) {
    const double a = a0 + (a1 - a0) * i / segments;
    pts.push_back({centre.x + r * std::cos(a), centre.y + r * std::sin(a)});
  }
  pts.front() = from;
  pts.back() = to;
  return pts;
}

// A closed polyline through the corners of an axis-aligned rectangle, `per_side` segments a side,
// counter-clockwise when ccw, else clockwise (for holes).
inline std::vector<Vec2> rectangle(Vec2 lo, Vec2 hi, int per_side, bool ccw) {
  const Vec2 corners[4] = {lo, {hi.x, lo.y}, hi, {lo.x, hi.y}};
  std::vector<Vec2> pts;
  for (int side = 0; side < 4; ++side) {
    const Vec2 a = corners[side], b = corners[(side + 1) % 4];
    for (int i = 0; i < per_side; ++i) {
      const double t = static_cast<double>(i) / per_side;
      pts.push_back({a.x + t * (b.x - a.x), a.y + t * (b.y - a.y)});
    }
  }
  pts.push_back(lo);
  if (!ccw) std::reverse(pts.begin(), pts.end());
  return pts;
}

// Circle (radius 10) within circle (radius 3), each made of two semicircle curves (thesis fig. 4.1).
inline Geometry circle_in_circle() {
  const double pi = std::acos(-1.0);
  return make_geometry(
      {arc_points({0, 0}, 10, 0, pi, 37, {10, 0}, {-10, 0}), arc_points({0, 0}, 10, pi, 2 * pi, 41, {-10, 0}, {10, 0}),
       arc_points({0, 0}, 3, 0, pi, 13, {3, 0}, {-3, 0}), arc_points({0, 0}, 3, pi, 2 * pi, 17, {-3, 0}, {3, 0})});
}

// The square [0,4]^2 (4 segments a side) with the square hole [1.5,2.5]^2 (1 segment a side).
inline Geometry square_with_hole() {
  return make_geometry({rectangle({0, 0}, {4, 4}, 4, true), rectangle({1.5, 1.5}, {2.5, 2.5}, 1, false)});
}

using pdmesh_test::unit;  // 53 random bits mapped to [0, 1) (seeded_random.hpp)

// A star-shaped polygon with n vertices at random radii in [1, 2]: many short, jagged segments.
inline Geometry jagged_polygon(int n, std::uint64_t seed) {
  const double pi = std::acos(-1.0);
  std::mt19937_64 rng(seed);
  std::vector<Vec2> pts;
  for (int i = 0; i < n; ++i) {
    const double a = 2 * pi * i / n;
    const double r = 1.0 + unit(rng);
    pts.push_back({r * std::cos(a), r * std::sin(a)});
  }
  pts.push_back(pts.front());
  return make_geometry({pts});
}

// Features 1000x apart in size: a 1000 x 1000 square (four side curves), a radius-0.5 circular hole
// and a triangle hole with sides about 0.01.
inline Geometry multiscale() {
  const double pi = std::acos(-1.0);
  const Vec2 c{300.3, 700.7};
  return make_geometry({{{0, 0}, {250, 0}, {500, 0}, {750, 0}, {1000, 0}},
                        {{1000, 0}, {1000, 500}, {1000, 1000}},
                        {{1000, 1000}, {0, 1000}},
                        {{0, 1000}, {0, 333}, {0, 0}},
                        arc_points(c, 0.5, 0, 2 * pi, 64, {c.x + 0.5, c.y}, {c.x + 0.5, c.y}),
                        {{600.0, 200.0}, {600.01, 200.0}, {600.005, 200.0087}, {600.0, 200.0}}});
}

// A closed circle of radius r centred at the origin as one raw curve of n segments, its first point
// at angle a0 (repeated at the end), for build_geometry.
inline RawCurve circle_curve(double r, int n, double a0 = 0.0, const std::string& name = "circle") {
  RawCurve c{name, {}, "test", 1, {}};
  for (int i = 0; i < n; ++i) {
    const double a = a0 + 2.0 * std::acos(-1.0) * i / n;
    c.points.push_back({r * std::cos(a), r * std::sin(a)});
  }
  c.points.push_back(c.points.front());
  return c;
}

// q = a constant everywhere.
struct ConstantSpacing final : SpacingField {
  explicit ConstantSpacing(double v) : q(v) {}
  double at(Vec2) const override { return q; }
  double q;
};

// Points from a to b in `segments` equal segments, with both ends exactly a and b.
inline std::vector<Vec2> line(Vec2 a, Vec2 b, int segments) {
  std::vector<Vec2> p;
  for (int i = 0; i <= segments; ++i) {
    const double t = static_cast<double>(i) / segments;
    p.push_back(i == 0 ? a : i == segments ? b : Vec2{a.x + t * (b.x - a.x), a.y + t * (b.y - a.y)});
  }
  return p;
}

// An L x L square with corner o as four curves "side0".."side3" of m equal segments each
// (counter-clockwise), through build_geometry.
inline Geometry square(double L, int m, Vec2 o = {0, 0}) {
  const Vec2 c[4] = {{o.x, o.y}, {o.x + L, o.y}, {o.x + L, o.y + L}, {o.x, o.y + L}};
  std::vector<RawCurve> raw;
  for (int k = 0; k < 4; ++k) {
    RawCurve curve;
    curve.name = "side" + std::to_string(k);
    curve.points = line(c[k], c[(k + 1) % 4], m);
    raw.push_back(std::move(curve));
  }
  return build_geometry(std::move(raw));
}

// Distance from p to the closest segment by a scan of every segment: an oracle independent of
// GeometryTree.
inline double brute_distance(const Geometry& g, Vec2 p) {
  double best = INFINITY;
  for (const Segment& s : g.segments) {
    const Vec2 d = s.b - s.a;
    const double t = std::clamp(dot(p - s.a, d) / norm2(d), 0.0, 1.0);
    best = std::fmin(best, dist(p, s.a + t * d));
  }
  return best;
}

}  // namespace pdmesh::fixtures
