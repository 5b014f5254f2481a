// Embedded constraints and points (docs/geometry-input.md, "Embedded constraints"): build_geometry's
// meeting points, refusals and inside checks, then whole runs on a square with a crack, a T-junction,
// a crossing, a levee from the boundary, a closed subdomain loop and embedded points, checked edge by
// edge against the input.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <map>
#include <numbers>
#include <set>
#include <string>
#include <vector>

#include "app/config/case_file.hpp"
#include "app/pipeline/mesh_inputs.hpp"
#include "app/pipeline/mesh_pipeline.hpp"
#include "core/errors.hpp"
#include "geometry/geometry.hpp"
#include "geometry/geometry_tree.hpp"
#include "io/mesh_formats.hpp"
#include "mesh/mesh_check.hpp"
#include "mesh/quality.hpp"
#include "temp_files.hpp"

using namespace pdmesh;
using Catch::Matchers::Contains;

namespace {

RawCurve curve(std::vector<Vec2> points, std::string name, bool constraint = false, int line = 1) {
  RawCurve c;
  c.name = std::move(name);
  c.points = std::move(points);
  c.file = "test.crv";
  c.line = line;
  c.constraint = constraint;
  return c;
}

RawCurve unit_square() { return curve({{0, 0}, {1, 0}, {1, 1}, {0, 1}, {0, 0}}, "square"); }

// The critical point at p, or nullptr.
const CriticalPoint* critical_at(const Geometry& g, Vec2 p) {
  for (const CriticalPoint& cp : g.critical)
    if (cp.p == p) return &cp;
  return nullptr;
}

bool has_vertex(const Curve& c, Vec2 p) { return std::find(c.points.begin(), c.points.end(), p) != c.points.end(); }

}  // namespace

TEST_CASE("constraints: an open crack joins no loop and keeps the domain", "[geometry][constraints]") {
  RawGeometry raw;
  raw.curves = {unit_square(), curve({{0.2, 0.3}, {0.5, 0.4}, {0.8, 0.35}}, "crack", true)};
  const Geometry g = build_geometry(raw);
  REQUIRE(g.curves.size() == 2);
  CHECK(g.curves[1].constraint);
  REQUIRE(g.loops.size() == 1);
  CHECK(g.loops[0].curves == std::vector<int>{0});
  CHECK(g.area == 1.0);
  // Every crack vertex is a critical point of the crack alone (its middle one too: a constraint's
  // input vertices are kept).
  REQUIRE(critical_at(g, {0.2, 0.3}) != nullptr);
  REQUIRE(critical_at(g, {0.8, 0.35}) != nullptr);
  CHECK(critical_at(g, {0.2, 0.3})->curves == std::vector<int>{1});
  REQUIRE(critical_at(g, {0.5, 0.4}) != nullptr);
  CHECK(g.curves[0].critical == std::vector<std::uint8_t>{1, 1, 1, 1, 1});
  // The tree's inside test and crossing test do not see the crack.
  const GeometryTree tree(g);
  CHECK(tree.inside({0.5, 0.2}));
  CHECK(tree.inside({0.5, 0.6}));
  CHECK_FALSE(tree.crosses_boundary({0.5, 0.2}, {0.5, 0.6}));
  CHECK(tree.crosses_boundary({0.5, 0.5}, {1.5, 0.5}));
  // closest() sees it (feature size, clearances); closest_wall() does not.
  CHECK(g.segments[static_cast<std::size_t>(tree.closest({0.5, 0.41}).segment)].curve == 1);
  CHECK(g.segments[static_cast<std::size_t>(tree.closest_wall({0.5, 0.41}).segment)].curve == 0);
}

TEST_CASE("constraints: a T-junction and a crossing become shared critical vertices", "[geometry][constraints]") {
  RawGeometry raw;
  raw.curves = {unit_square(), curve({{0.2, 0.5}, {0.8, 0.5}}, "bar", true),
                curve({{0.5, 0.2}, {0.5, 0.5}}, "stem", true),    // ends on the bar: a T
                curve({{0.3, 0.3}, {0.3, 0.7}}, "cross", true)};  // crosses the bar at (0.3, 0.5)
  const Geometry g = build_geometry(raw);
  CHECK(has_vertex(g.curves[1], {0.5, 0.5}));
  CHECK(has_vertex(g.curves[1], {0.3, 0.5}));
  CHECK(has_vertex(g.curves[3], {0.3, 0.5}));
  CHECK(g.curves[1].points.size() == 4);
  const CriticalPoint* t = critical_at(g, {0.5, 0.5});
  REQUIRE(t != nullptr);
  CHECK(std::set<int>(t->curves.begin(), t->curves.end()) == std::set<int>{1, 2});
  const CriticalPoint* x = critical_at(g, {0.3, 0.5});
  REQUIRE(x != nullptr);
  CHECK(std::set<int>(x->curves.begin(), x->curves.end()) == std::set<int>{1, 3});
  CHECK(g.area == 1.0);
}

TEST_CASE("constraints: a levee from the boundary splits the boundary curve there", "[geometry][constraints]") {
  RawGeometry raw;
  raw.curves = {unit_square(), curve({{0.0, 0.5}, {0.4, 0.5}}, "levee", true)};
  const Geometry g = build_geometry(raw);
  CHECK(has_vertex(g.curves[0], {0.0, 0.5}));
  const CriticalPoint* cp = critical_at(g, {0.0, 0.5});
  REQUIRE(cp != nullptr);
  CHECK(std::set<int>(cp->curves.begin(), cp->curves.end()) == std::set<int>{0, 1});
  // An end within the join tolerance of the boundary joins it too.
  raw.curves[1].points[0] = {1e-12, 0.5};
  const Geometry near = build_geometry(raw);
  REQUIRE(critical_at(near, {1e-12, 0.5}) != nullptr);
  CHECK(critical_at(near, {1e-12, 0.5})->curves.size() == 2);
  CHECK(has_vertex(near.curves[0], {1e-12, 0.5}));
}

TEST_CASE("constraints: a crossing a rounding away from a vertex is at the vertex", "[geometry][constraints]") {
  // An end computed in the middle of a rotated boundary segment lies a rounding beyond it: the end
  // is the meeting point, with no sliver segment past it.
  std::vector<Vec2> ring;
  for (int i = 0; i < 12; ++i) ring.push_back({std::cos(std::numbers::pi * i / 6), std::sin(std::numbers::pi * i / 6)});
  ring.push_back(ring.front());
  const Vec2 mid = 0.5 * (ring[0] + ring[1]);
  RawGeometry raw;
  raw.curves = {curve(ring, "wall"), curve({0.6 * mid, mid}, "spoke", true)};
  const Geometry g = build_geometry(raw);
  CHECK(g.curves[1].points == std::vector<Vec2>{0.6 * mid, mid});
  CHECK(has_vertex(g.curves[0], mid));
  // A line through a constraint's vertex that rounding puts a hair off it meets it at the vertex.
  Vec2 v = Vec2{0.6, 0.6} + 0.5 * (Vec2{0.9, 0.9} - Vec2{0.6, 0.6});
  v.x = std::nextafter(v.x, 1.0);
  raw.curves = {unit_square(), curve({{0.75, 0.25}, v, {0.25, 0.75}}, "roof", true),
                curve({{0.6, 0.6}, {0.9, 0.9}}, "ray", true)};
  const Geometry h = build_geometry(raw);
  CHECK(h.curves[1].points.size() == 3);
  CHECK(h.curves[2].points.size() == 3);
  CHECK(h.curves[2].points[1] == h.curves[1].points[1]);
}

TEST_CASE("constraints: embedded points inside, on a curve, duplicated", "[geometry][constraints]") {
  RawGeometry raw;
  raw.curves = {unit_square(), curve({{0.2, 0.5}, {0.8, 0.5}}, "bar", true)};
  raw.points = {{{0.25, 0.75}, "pts", 3}, {{0.25, 0.75}, "pts", 4}, {{0.6, 0.5}, "pts", 5}};
  const Geometry g = build_geometry(raw);
  REQUIRE(g.embedded_points.size() == 1);
  CHECK(g.embedded_points[0].p == Vec2{0.25, 0.75});
  CHECK(g.embedded_points[0].file == "pts");
  CHECK(g.embedded_points[0].line == 3);
  CHECK(has_vertex(g.curves[1], {0.6, 0.5}));
  REQUIRE(critical_at(g, {0.6, 0.5}) != nullptr);
}

TEST_CASE("constraints: without constraints and points the RawGeometry overload is the old one",
          "[geometry][constraints]") {
  RawGeometry raw;
  raw.curves = {unit_square(), curve({{0.3, 0.3}, {0.6, 0.3}, {0.6, 0.6}, {0.3, 0.3}}, "hole")};
  const Geometry a = build_geometry(raw);
  const Geometry b = build_geometry(raw.curves);
  REQUIRE(a.critical.size() == b.critical.size());
  for (std::size_t k = 0; k < a.critical.size(); ++k) {
    CHECK(a.critical[k].p == b.critical[k].p);
    CHECK(a.critical[k].curves == b.critical[k].curves);
  }
  CHECK(a.area == b.area);
}

TEST_CASE("constraints: refused outside the domain, in a hole, along a curve", "[geometry][constraints]") {
  const RawCurve hole = curve({{0.3, 0.3}, {0.6, 0.3}, {0.6, 0.6}, {0.3, 0.6}, {0.3, 0.3}}, "hole");
  RawGeometry raw;
  raw.curves = {unit_square(), curve({{1.2, 0.5}, {1.5, 0.5}}, "far", true, 7)};
  CHECK_THROWS_WITH(build_geometry(raw), Contains("test.crv:7") &&
                                             Contains("constraint curve 'far' leaves the domain") &&
                                             Contains("(1.2, 0.5)"));
  // Partly outside: it crosses the boundary (split there), the outer piece is named.
  raw.curves[1] = curve({{0.5, 0.5}, {1.5, 0.5}}, "out", true, 9);
  CHECK_THROWS_WITH(build_geometry(raw), Contains("test.crv:10") && Contains("'out'") && Contains("(1.5, 0.5)"));
  // In a hole.
  raw.curves = {unit_square(), hole, curve({{0.4, 0.4}, {0.5, 0.5}}, "inhole", true, 11)};
  CHECK_THROWS_WITH(build_geometry(raw), Contains("'inhole' leaves the domain"));
  // A point in the hole.
  raw.curves = {unit_square(), hole, curve({{0.1, 0.1}, {0.2, 0.2}}, "ok", true)};
  raw.points = {{{0.45, 0.45}, "pts.txt", 2}};
  CHECK_THROWS_WITH(build_geometry(raw),
                    Contains("pts.txt:2") && Contains("point (0.45, 0.45) lies outside the domain"));
  // Running along the boundary.
  raw.points.clear();
  raw.curves = {unit_square(), curve({{0.2, 0.0}, {0.7, 0.0}}, "along", true)};
  CHECK_THROWS_WITH(build_geometry(raw), Contains("overlaps"));
  // Constraints alone.
  raw.curves = {curve({{0.2, 0.0}, {0.7, 0.0}}, "alone", true)};
  CHECK_THROWS_AS(build_geometry(raw), GeometryError);
  // A self-crossing constraint is refused like a self-crossing boundary curve.
  raw.curves = {unit_square(), curve({{0.2, 0.2}, {0.8, 0.8}, {0.8, 0.2}, {0.2, 0.8}}, "zigzag", true)};
  CHECK_THROWS_WITH(build_geometry(raw), Contains("intersects itself"));
}

namespace {

struct Run {
  Geometry geometry;
  Mesh mesh;
};

// The whole pipeline on curves and points given in memory (the Python API's path), host backend,
// nothing written.
Mesh mesh_of(const std::vector<RawCurve>& curves, const std::vector<RawPoint>& points, Geometry& geometry,
             const std::vector<std::string>& settings = {}) {
  std::vector<CaseOverride> overrides = {parse_set_option("simulation.device=host")};
  for (const std::string& s : settings) overrides.push_back(parse_set_option(s));
  CaseConfig config = case_for_curves(curves, "constraints", overrides);
  config.geometry.given_points = points;
  config.write_outputs = false;
  config.quiet = true;
  MeshInputs inputs(config);
  SpacingStage spacing(config, inputs);
  check_node_limit(config, inputs, spacing);
  InitialDistribution initial = make_initial(config, inputs, spacing);
  simulate(config, inputs, spacing, initial.nodes);
  Mesh mesh = mesh_and_measure(config, inputs, spacing, initial.nodes);
  geometry = inputs.geometry;
  return mesh;
}

// Every input segment of every constraint is covered by a chain of mesh edges lying on it; every
// input vertex and point is a node; the mesh is valid; returns the smallest angle.
double check_constrained(const Geometry& g, const Mesh& mesh, const std::vector<Vec2>& input_vertices) {
  const CheckReport report = check_mesh(mesh, g.area);
  INFO(report.summary());
  CHECK(report.problems.empty());
  std::set<std::pair<int, int>> edges;
  for (const auto& t : mesh.triangles)
    for (int i = 0; i < 3; ++i) edges.insert(std::minmax(t[i], t[(i + 1) % 3]));
  auto node_at = [&](Vec2 p) {
    const auto it = std::find(mesh.points.begin(), mesh.points.end(), p);
    return it == mesh.points.end() ? -1 : static_cast<int>(it - mesh.points.begin());
  };
  for (const Vec2 p : input_vertices) {
    INFO("input vertex (" << p.x << ", " << p.y << ")");
    CHECK(node_at(p) >= 0);
  }
  // Each constraint's boundary edges form one chain of mesh edges from its first input point to its
  // last, through every input point in order, every node of it on the input polyline.
  for (std::size_t c = 0; c < g.curves.size(); ++c) {
    const Curve& curve = g.curves[c];
    if (!curve.constraint) continue;
    INFO("constraint " << curve.name);
    std::vector<int> chain;
    for (const BoundaryEdge& e : mesh.boundary_edges) {
      if (e.curve != static_cast<int>(c)) continue;
      if (chain.empty()) chain.push_back(e.a);
      CHECK(chain.back() == e.a);
      chain.push_back(e.b);
      CHECK(edges.count(std::minmax(e.a, e.b)));
    }
    REQUIRE(chain.size() >= 2);
    std::size_t next = 0;  // the next input point to meet along the chain
    for (const int node : chain) {
      const Vec2 p = mesh.points[static_cast<std::size_t>(node)];
      if (next < curve.points.size() && p == curve.points[next]) ++next;
      double d = HUGE_VAL;
      for (std::size_t k = 0; k + 1 < curve.points.size(); ++k) {
        const Vec2 a = curve.points[k], b = curve.points[k + 1];
        const double t = std::clamp(dot(p - a, b - a) / dot(b - a, b - a), 0.0, 1.0);
        d = std::min(d, dist(p, a + t * (b - a)));
      }
      CHECK(d <= 1e-12);
    }
    CHECK(next == curve.points.size());
    CHECK(mesh.points[static_cast<std::size_t>(chain.front())] == curve.points.front());
    CHECK(mesh.points[static_cast<std::size_t>(chain.back())] == curve.points.back());
  }
  double smallest = 180.0;
  for (const auto& t : mesh.triangles)
    smallest = std::min(smallest, triangle_shape(mesh.points[t[0]], mesh.points[t[1]], mesh.points[t[2]]).min_angle);
  return smallest;
}

// A square of side 1 in 4 segments per side, so that the field (eq. 3.6 of the segments) is about 0.25.
RawCurve square_boundary() {
  std::vector<Vec2> pts;
  for (int i = 0; i < 4; ++i) pts.push_back({i / 4.0, 0.0});
  for (int i = 0; i < 4; ++i) pts.push_back({1.0, i / 4.0});
  for (int i = 0; i < 4; ++i) pts.push_back({1.0 - i / 4.0, 1.0});
  for (int i = 0; i <= 4; ++i) pts.push_back({0.0, 1.0 - i / 4.0});
  return curve(pts, "square");
}

}  // namespace

TEST_CASE("constraints, whole run: the plain square's minimum angle for reference", "[app][constraints]") {
  Geometry g;
  const Mesh mesh = mesh_of({square_boundary()}, {}, g);
  const double angle = check_constrained(g, mesh, {});
  CHECK(angle >= 30.0);
}

TEST_CASE("constraints, whole run: a crack, a T, a crossing, a levee and points", "[app][constraints]") {
  const std::vector<RawCurve> curves = {square_boundary(),
                                        curve({{0.15, 0.3}, {0.45, 0.35}, {0.7, 0.3}}, "crack", true),
                                        curve({{0.2, 0.7}, {0.8, 0.7}}, "bar", true),
                                        curve({{0.5, 0.5}, {0.5, 0.7}}, "stem", true),     // a T under the bar
                                        curve({{0.3, 0.6}, {0.3, 0.85}}, "cross", true),   // crosses the bar
                                        curve({{1.0, 0.45}, {0.8, 0.5}}, "levee", true)};  // from the boundary inland
  const std::vector<RawPoint> points = {{{0.8, 0.15}, "pts", 1}, {{0.2, 0.12}, "pts", 2}};
  Geometry g;
  const Mesh mesh = mesh_of(curves, points, g);
  std::vector<Vec2> vertices = {{0.8, 0.15}, {0.2, 0.12}, {0.3, 0.7}, {0.5, 0.7}, {1.0, 0.45}};
  for (std::size_t c = 1; c < curves.size(); ++c)
    for (const Vec2 p : curves[c].points) vertices.push_back(p);
  const double angle = check_constrained(g, mesh, vertices);
  CHECK(angle >= 30.0);
  // The constraint edges carry their curves, and the mesh files keep them by name (line elements
  // in .msh, markers in .su2, segments in Triangle's .poly).
  REQUIRE(mesh.constraint_curves.size() == curves.size());
  std::map<std::string, std::size_t> per_curve;
  for (const BoundaryEdge& e : mesh.boundary_edges) ++per_curve[mesh.curve_names[static_cast<std::size_t>(e.curve)]];
  CHECK(per_curve.size() == curves.size());
  const auto dir = pdmesh_test::fresh_dir("constraints_formats");
  write_mesh(mesh, dir, "mesh", {"msh", "su2", "triangle"});
  for (const char* file : {"mesh.msh", "mesh.su2", "mesh.ele"}) {
    INFO(file);
    const Mesh back = read_mesh(dir / file);
    CHECK(back.triangles.size() == mesh.triangles.size());
    std::map<std::string, std::size_t> back_per_curve;
    for (const BoundaryEdge& e : back.boundary_edges)
      ++back_per_curve[back.curve_names.empty() ? std::to_string(e.curve)
                                                : back.curve_names[static_cast<std::size_t>(e.curve)]];
    if (std::string(file) != "mesh.ele")
      CHECK(back_per_curve == per_curve);
    else
      CHECK(back.boundary_edges.size() == mesh.boundary_edges.size());
  }
  std::filesystem::remove_all(dir);
}

TEST_CASE("constraints, whole run: a closed constraint loop bounds a subdomain, not a hole", "[app][constraints]") {
  const std::vector<RawCurve> curves = {
      square_boundary(), curve({{0.3, 0.3}, {0.7, 0.3}, {0.7, 0.7}, {0.3, 0.7}, {0.3, 0.3}}, "region", true)};
  Geometry g;
  const Mesh mesh = mesh_of(curves, {}, g);
  double area = 0.0;
  for (const auto& t : mesh.triangles)
    area += 0.5 * cross(mesh.points[t[1]] - mesh.points[t[0]], mesh.points[t[2]] - mesh.points[t[0]]);
  CHECK(area == Approx(1.0).epsilon(1e-12));
  const double angle = check_constrained(g, mesh, curves[1].points);
  CHECK(angle >= 30.0);
}

TEST_CASE("constraints, pdmesh mesh: a constraint outside or a point in a hole writes nothing", "[app][constraints]") {
  const RawCurve hole = curve({{0.3, 0.3}, {0.6, 0.3}, {0.6, 0.6}, {0.3, 0.6}, {0.3, 0.3}}, "hole");
  for (int k = 0; k < 2; ++k) {
    std::vector<RawCurve> curves = {unit_square(), hole};
    std::vector<RawPoint> points;
    if (k == 0) curves.push_back(curve({{0.8, 0.5}, {1.3, 0.5}}, "out", true));
    if (k == 1) points.push_back({{0.4, 0.4}, "pts", 1});
    CaseConfig config = case_for_curves(curves, "bad", {});
    config.geometry.given_points = points;
    config.out_dir = pdmesh_test::fresh_path("constraints_bad");
    config.quiet = true;
    CHECK_THROWS_AS(run_mesh(config), GeometryError);
    CHECK_FALSE(std::filesystem::exists(config.out_dir));
  }
}
