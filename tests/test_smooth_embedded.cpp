// Smooth curves with embedded constraints and points (docs/geometry-input.md, "Smooth curves"):
// constraints smoothed like boundary curves, a constraint's end in the middle of a boundary segment
// and a crossing of two constraints moved onto the smooth curves, the checks that send a run back
// to the polylines, and a whole run whose constraint edges lie on the smooth constraint.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "app/config/case_file.hpp"
#include "app/pipeline/mesh_inputs.hpp"
#include "app/pipeline/mesh_pipeline.hpp"
#include "core/errors.hpp"
#include "geometry/geometry.hpp"
#include "geometry/smooth_curve.hpp"
#include "geometry/smooth_embedded.hpp"

using namespace pdmesh;
using Catch::Matchers::Contains;

namespace {

RawCurve curve(std::vector<Vec2> points, std::string name, bool constraint = false) {
  RawCurve c;
  c.name = std::move(name);
  c.points = std::move(points);
  c.file = "test.crv";
  c.line = 1;
  c.constraint = constraint;
  return c;
}

// A closed polygon of n points on the circle of radius r about c, starting at angle `start`.
std::vector<Vec2> circle(Vec2 c, double r, int n, double start = 0.0) {
  std::vector<Vec2> p;
  for (int i = 0; i < n; ++i) {
    const double a = start + 2.0 * std::numbers::pi * i / n;
    p.push_back(c + Vec2{r * std::cos(a), r * std::sin(a)});
  }
  p.push_back(p.front());
  return p;
}

// Points on the circle of radius r about the origin from angle a0 to a1 (degrees), n segments.
std::vector<Vec2> arc(double r, double a0, double a1, int n) {
  std::vector<Vec2> p;
  for (int i = 0; i <= n; ++i) {
    const double a = (a0 + (a1 - a0) * i / n) * std::numbers::pi / 180.0;
    p.push_back({r * std::cos(a), r * std::sin(a)});
  }
  return p;
}

// The chord error of a polyline of segments subtending `deg` degrees on a circle of radius r.
double sagitta(double r, double deg) { return r * (1.0 - std::cos(deg * std::numbers::pi / 360.0)); }

int curve_named(const Geometry& g, const std::string& name) {
  for (std::size_t c = 0; c < g.curves.size(); ++c)
    if (g.curves[c].name == name) return static_cast<int>(c);
  return -1;
}

bool has_vertex(const Curve& c, Vec2 p) { return std::find(c.points.begin(), c.points.end(), p) != c.points.end(); }

// A unit circle of 16 segments, an arc constraint of radius 0.5 (5 segments of 24 degrees), a
// spoke constraint ending in the middle of the circle's segment from 0 to 22.5 degrees, a point.
// (Turns well below the corner angle of 30 degrees: a polygon turning by exactly it would have
// corners where rounding puts the turn above.)
RawGeometry circle_with_spoke() {
  RawGeometry raw;
  const Vec2 mid = 0.5 * (Vec2{1.0, 0.0} + Vec2{std::cos(std::numbers::pi / 8), std::sin(std::numbers::pi / 8)});
  raw.curves = {curve(circle({0, 0}, 1.0, 16), "wall"), curve(arc(0.5, -60.0, 60.0, 5), "arc", true),
                curve({0.6 * (1.0 / norm(mid)) * mid, mid}, "spoke", true)};
  raw.points = {{{-0.3, 0.2}, "pts", 7}};
  return raw;
}

}  // namespace

TEST_CASE("smooth embedded: constraints are smoothed, a mid-segment end moves onto the smooth wall",
          "[geometry][smooth][constraints]") {
  const RawGeometry raw = circle_with_spoke();
  const Vec2 mid = raw.curves[2].points[1];
  const Geometry g = build_geometry(raw);
  const DenseGeometry d = make_dense_embedded(g, 30.0, [](Vec2) { return 0.1; });
  const Geometry& dg = d.geometry;
  const int wall = curve_named(dg, "wall"), arc_c = curve_named(dg, "arc"), spoke = curve_named(dg, "spoke");
  REQUIRE(wall >= 0);
  REQUIRE(arc_c >= 0);
  REQUIRE(spoke >= 0);
  CHECK(dg.curves[static_cast<std::size_t>(arc_c)].constraint);
  CHECK(dg.curves[static_cast<std::size_t>(spoke)].constraint);
  CHECK_FALSE(dg.curves[static_cast<std::size_t>(wall)].constraint);
  // The wall is smooth through its 16 points and not pulled to the chord at the spoke's end: every
  // dense vertex within a tenth of the polyline's chord error of the unit circle.
  const double wall_sag = sagitta(1.0, 22.5);
  double worst_wall = 0.0;
  for (const Vec2 p : dg.curves[static_cast<std::size_t>(wall)].points)
    worst_wall = std::max(worst_wall, std::fabs(norm(p) - 1.0));
  CHECK(worst_wall <= 0.1 * wall_sag);
  // The arc constraint is smooth too (the polyline's chords are up to 0.011 inside the circle).
  double worst_arc = 0.0;
  for (const Vec2 p : dg.curves[static_cast<std::size_t>(arc_c)].points)
    worst_arc = std::max(worst_arc, std::fabs(norm(p) - 0.5));
  CHECK(dg.curves[static_cast<std::size_t>(arc_c)].points.size() > 5);
  CHECK(worst_arc <= 0.1 * sagitta(0.5, 24.0));
  // The spoke's end moved off the chord onto the smooth wall, is a dense vertex of the wall and one
  // critical point of both curves; its other end stays.
  const Curve& sp = dg.curves[static_cast<std::size_t>(spoke)];
  const Vec2 end = sp.points.back();
  CHECK(sp.points.front() == raw.curves[2].points[0]);
  CHECK(std::fabs(norm(end) - 1.0) <= 0.1 * wall_sag);
  CHECK(dist(end, mid) >= 0.5 * wall_sag);
  CHECK(has_vertex(dg.curves[static_cast<std::size_t>(wall)], end));
  const auto at_end =
      std::find_if(dg.critical.begin(), dg.critical.end(), [&](const CriticalPoint& cp) { return cp.p == end; });
  REQUIRE(at_end != dg.critical.end());
  CHECK(at_end->curves.size() == 2);
  // Every critical point is the dense point at each of its indices; every input point of the arc
  // and the wall is a dense vertex where it was.
  REQUIRE(dg.critical.size() == g.critical.size());
  for (const CriticalPoint& cp : dg.critical)
    for (std::size_t k = 0; k < cp.curves.size(); ++k)
      CHECK(dg.curves[static_cast<std::size_t>(cp.curves[k])].points[static_cast<std::size_t>(cp.indices[k])] == cp.p);
  for (const int c : {wall, arc_c})
    for (std::size_t i = 0; i < g.curves[static_cast<std::size_t>(c)].points.size(); ++i) {
      const Vec2 p = g.curves[static_cast<std::size_t>(c)].points[i];
      if (p == mid) continue;
      CHECK(dg.curves[static_cast<std::size_t>(c)]
                .points[static_cast<std::size_t>(d.vertex[static_cast<std::size_t>(c)][i])] == p);
    }
  // The point is kept; the dense segments know their input segments.
  REQUIRE(dg.embedded_points.size() == 1);
  CHECK(dg.embedded_points[0].p == Vec2{-0.3, 0.2});
  REQUIRE(d.source.size() == dg.segments.size());
  for (std::size_t j = 0; j < d.source.size(); ++j)
    CHECK(g.segments[static_cast<std::size_t>(d.source[j])].curve == dg.segments[j].curve);
}

TEST_CASE("smooth embedded: two constraints crossing mid-segment cross at a shared dense vertex",
          "[geometry][smooth][constraints]") {
  RawGeometry raw;
  raw.curves = {curve({{-1, -1}, {1, -1}, {1, 1}, {-1, 1}, {-1, -1}}, "box"),
                curve({{-0.6, -0.1}, {-0.2, 0.05}, {0.2, 0.05}, {0.6, -0.1}}, "cap", true),
                curve({{-0.1, -0.6}, {0.05, -0.2}, {0.05, 0.2}, {-0.1, 0.6}}, "side", true)};
  const Geometry g = build_geometry(raw);
  const DenseGeometry d = make_dense_embedded(g, 30.0, [](Vec2) { return 0.05; });
  const Curve& cap = d.geometry.curves[1];
  const Curve& side = d.geometry.curves[2];
  // The polylines cross at (0.05, 0.05), inside a segment of each; the smooth curves bulge past it.
  int shared = 0;
  Vec2 at;
  for (const Vec2 p : cap.points)
    if (has_vertex(side, p)) {
      ++shared;
      at = p;
    }
  REQUIRE(shared == 1);
  CHECK(at != Vec2{0.05, 0.05});
  CHECK(dist(at, {0.05, 0.05}) < 0.05);
  const auto cp = std::find_if(d.geometry.critical.begin(), d.geometry.critical.end(),
                               [&](const CriticalPoint& c) { return c.p == at; });
  REQUIRE(cp != d.geometry.critical.end());
  CHECK(cp->curves.size() == 2);
}

TEST_CASE("smooth embedded: constraint ends that meet on the boundary are free ends",
          "[geometry][smooth][constraints]") {
  // Two straight borders meet the bottom of the square end to end at (0.5, 0), turning by 21 degrees
  // there. Joined as one smooth line their common tangent would point up at P, the first border
  // dipping below y = 0 before it; as free ends each stays its own straight line.
  RawGeometry raw;
  raw.curves = {curve({{0, 0}, {1, 0}, {1, 1}, {0, 1}, {0, 0}}, "box"), curve({{0.1, 0.05}, {0.5, 0.0}}, "left", true),
                curve({{0.5, 0.0}, {0.9, 0.1}}, "right", true)};
  const Geometry g = build_geometry(raw);
  const DenseGeometry d = make_dense_embedded(g, 30.0, [](Vec2) { return 0.05; });
  CHECK(d.geometry.curves[1].points == g.curves[1].points);
  CHECK(d.geometry.curves[2].points == g.curves[2].points);
}

TEST_CASE("smooth embedded: without constraints and points it is make_dense_geometry", "[geometry][smooth]") {
  const Geometry g = build_geometry(
      std::vector<RawCurve>{curve(circle({0, 0}, 1.0, 12), "wall"), curve(circle({0, 0}, 0.3, 8, 0.1), "hole")});
  const auto q = [](Vec2 p) { return 0.05 + 0.1 * std::fabs(p.x); };
  const DenseGeometry a = make_dense_embedded(g, 30.0, q);
  const DenseGeometry b = make_dense_geometry(SmoothCurves(g, 30.0), q);
  REQUIRE(a.geometry.curves.size() == b.geometry.curves.size());
  for (std::size_t c = 0; c < a.geometry.curves.size(); ++c)
    CHECK(a.geometry.curves[c].points == b.geometry.curves[c].points);
  CHECK(a.vertex == b.vertex);
}

TEST_CASE("smooth embedded: a point in the smooth hole, a constraint bulging across another are refused",
          "[geometry][smooth][constraints]") {
  SECTION("a point between a hole's chord and its smooth curve") {
    RawGeometry raw;
    raw.curves = {curve({{-1, -1}, {1, -1}, {1, 1}, {-1, 1}, {-1, -1}}, "box"), curve(circle({0, 0}, 0.3, 16), "hole")};
    // At 11.25 degrees, between the 16-gon's chord (radius 0.2942) and the circle (0.3).
    const double a = std::numbers::pi / 16;
    raw.points = {{{0.298 * std::cos(a), 0.298 * std::sin(a)}, "pts", 7}};
    const Geometry g = build_geometry(raw);
    REQUIRE(g.embedded_points.size() == 1);
    CHECK_THROWS_WITH(make_dense_embedded(g, 30.0, [](Vec2) { return 0.05; }), Contains("pts:7"));
  }
  SECTION("an arc's smooth curve crosses a bar that its chord does not reach") {
    const Vec2 dir20{std::cos(std::numbers::pi / 9), std::sin(std::numbers::pi / 9)};
    RawGeometry raw;
    raw.curves = {curve({{-1, -1}, {1, -1}, {1, 1}, {-1, 1}, {-1, -1}}, "box"),
                  curve(arc(0.5, 0.0, 90.0, 2), "arc", true), curve({0.47 * dir20, 0.56 * dir20}, "bar", true)};
    const Geometry g = build_geometry(raw);
    // The polylines do not meet: the arc's chord passes 20 degrees up at radius 0.462.
    REQUIRE(g.curves[1].points.size() == 3);
    REQUIRE(g.curves[2].points.size() == 2);
    // A corner angle above the arc's 45-degree turn: one smooth arc through its three points.
    CHECK_THROWS_WITH(make_dense_embedded(g, 60.0, [](Vec2) { return 0.05; }),
                      Contains("meets") && Contains("arc") && Contains("bar"));
  }
}

namespace {

struct SmoothRun {
  std::string fallback;
  bool dense = false;
  Geometry node_geometry;
  Mesh mesh;
};

// The whole pipeline on curves and points given in memory, host backend, nothing written; the mesh
// invariant checker (--check) runs on the triangulation and the cleaned mesh and throws on a problem.
SmoothRun smooth_run(const RawGeometry& raw, const std::vector<std::string>& settings) {
  std::vector<CaseOverride> overrides = {parse_set_option("simulation.device=host"),
                                         parse_set_option("geometry.curves=smooth")};
  for (const std::string& s : settings) overrides.push_back(parse_set_option(s));
  CaseConfig config = case_for_curves(raw.curves, "smooth_embedded", overrides);
  config.geometry.given_points = raw.points;
  config.write_outputs = false;
  config.quiet = true;
  config.check = true;
  MeshInputs inputs(config);
  SmoothRun run;
  run.fallback = inputs.smooth_fallback;
  run.dense = inputs.dense != nullptr;
  run.node_geometry = inputs.node_geometry();
  SpacingStage spacing(config, inputs);
  check_node_limit(config, inputs, spacing);
  InitialDistribution initial = make_initial(config, inputs, spacing);
  simulate(config, inputs, spacing, initial.nodes);
  run.mesh = mesh_and_measure(config, inputs, spacing, initial.nodes);
  return run;
}

}  // namespace

TEST_CASE("smooth embedded, whole run: constraint edges on the smooth constraint, the point a node",
          "[app][smooth][constraints]") {
  const SmoothRun run = smooth_run(circle_with_spoke(), {"spacing.size=0.12"});
  INFO(run.fallback);
  CHECK(run.fallback.empty());
  REQUIRE(run.dense);
  const Mesh& mesh = run.mesh;
  CHECK(std::find(mesh.points.begin(), mesh.points.end(), Vec2{-0.3, 0.2}) != mesh.points.end());
  const int arc_c = curve_named(run.node_geometry, "arc");
  const int spoke = curve_named(run.node_geometry, "spoke");
  REQUIRE(arc_c >= 0);
  // The arc's edges chain from its first point to its last, every node on the smooth arc (the
  // polyline's nodes would be up to 0.011 inside it).
  std::size_t arc_edges = 0, spoke_edges = 0;
  double worst = 0.0;
  for (const BoundaryEdge& e : mesh.boundary_edges) {
    if (e.curve == spoke) ++spoke_edges;
    if (e.curve != arc_c) continue;
    ++arc_edges;
    for (const int v : {e.a, e.b})
      worst = std::max(worst, std::fabs(norm(mesh.points[static_cast<std::size_t>(v)]) - 0.5));
  }
  CHECK(arc_edges >= 5);
  CHECK(spoke_edges >= 2);
  CHECK(worst <= 0.1 * sagitta(0.5, 24.0));
  // The spoke ends on a wall node on the smooth wall.
  const Vec2 end = run.node_geometry.curves[static_cast<std::size_t>(spoke)].points.back();
  CHECK(std::find(mesh.points.begin(), mesh.points.end(), end) != mesh.points.end());
  CHECK(std::fabs(norm(end) - 1.0) <= 0.1 * sagitta(1.0, 22.5));
}

TEST_CASE("smooth embedded, whole run: a point in the smooth hole falls back to the polylines with a note",
          "[app][smooth][constraints]") {
  RawGeometry raw;
  raw.curves = {curve({{-1, -1}, {1, -1}, {1, 1}, {-1, 1}, {-1, -1}}, "box"), curve(circle({0, 0}, 0.3, 16), "hole")};
  const double a = std::numbers::pi / 16;
  raw.points = {{{0.298 * std::cos(a), 0.298 * std::sin(a)}, "pts", 7}};
  const SmoothRun run = smooth_run(raw, {"spacing.size=0.15"});
  CHECK_FALSE(run.dense);
  CHECK_THAT(run.fallback, Contains("pts:7") && Contains("outside the domain"));
  CHECK(std::find(run.mesh.points.begin(), run.mesh.points.end(), raw.points[0].p) != run.mesh.points.end());
}
