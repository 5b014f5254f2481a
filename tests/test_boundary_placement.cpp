// Tests of boundary.nodes: "spacing" places nodes at equal integral of ds/q between critical points
// (edges within 10% of q, critical points kept, nodes on the curve, the chord-deviation rule, the
// node limit); "input" is the thesis' rule through the same assembly; and a short run keeps the
// boundary nodes on the smooth curve.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <memory>
#include <numbers>

#include "app/config/case_file.hpp"
#include "app/pipeline/mesh_pipeline.hpp"
#include "core/errors.hpp"
#include "geometry/geometry.hpp"
#include "geometry/geometry_tree.hpp"
#include "geometry/smooth_curve.hpp"
#include "init/boundary_placement.hpp"
#include "init/initial_distribution.hpp"
#include "nodes/node_file.hpp"
#include "sim/boundary_handling.hpp"
#include "sim/simulation.hpp"
#include "spacing/spacing_field.hpp"
#include "geometry_fixtures.hpp"
#include "run_pdmesh.hpp"
#include "temp_files.hpp"

using namespace pdmesh;
using pdmesh::fixtures::ConstantSpacing;

namespace {

// A smoothly varying field: 0.25 to 0.75 along x over the test geometries.
struct WavySpacing final : SpacingField {
  double at(Vec2 p) const override { return 0.5 + 0.25 * std::sin(0.4 * p.x + 0.2 * p.y); }
};

// A 12 x 8 rectangle (2 points a side: coarser than any q here) with a circular hole of radius 2
// (40 points) at (6, 4). The bottom is three curves: one with a bump of 60- and 120-degree corners
// (critical), a curve of length 0.1, and the rest.
Geometry plate() {
  std::vector<RawCurve> raw;
  raw.push_back({"bottom", {{0, 0}, {5, 0}, {5.5, 0.866}, {6, 0}}, "test", 1, {}});
  raw.push_back({"bit", {{6, 0}, {6.1, 0}}, "test", 5, {}});
  raw.push_back({"bottom2", {{6.1, 0}, {12, 0}}, "test", 7, {}});
  raw.push_back({"right", {{12, 0}, {12, 8}}, "test", 10, {}});
  raw.push_back({"top", {{12, 8}, {0, 8}}, "test", 20, {}});
  raw.push_back({"left", {{0, 8}, {0, 0}}, "test", 30, {}});
  RawCurve hole = fixtures::circle_curve(2.0, 40, 0.0, "hole");
  for (Vec2& p : hole.points) p = p + Vec2{6, 4};
  raw.push_back(hole);
  return build_geometry(std::move(raw));
}

// Every boundary edge's length against q at its midpoint: the largest |length / q - 1| over the
// edges of curves with no interior corner and at least `min_edges` edges (a short section rounds
// its edge count).
double worst_edge_ratio(const NodeSet& nodes, const Geometry& g, const SpacingField& q, std::size_t min_edges) {
  double worst = 0.0;
  for (std::size_t c = 0; c < g.curves.size(); ++c) {
    const auto& list = nodes.curve_nodes[c];
    const auto& critical = g.curves[c].critical;
    if (list.size() < min_edges + 1 || std::count(critical.begin() + 1, critical.end() - 1, 1) > 0) continue;
    for (std::size_t k = 0; k + 1 < list.size(); ++k) {
      const Vec2 a = nodes.x[static_cast<std::size_t>(list[k])], b = nodes.x[static_cast<std::size_t>(list[k + 1])];
      worst = std::max(worst, std::fabs(dist(a, b) / q.at(0.5 * (a + b)) - 1.0));
    }
  }
  return worst;
}

}  // namespace

TEST_CASE("spacing nodes: edges within 10% of q at their midpoints under a smoothly varying field", "[placement]") {
  const Geometry g = plate();
  const WavySpacing q;
  for (const bool smooth : {false, true}) {
    INFO((smooth ? "smooth curves" : "polylines"));
    std::unique_ptr<DenseGeometry> dense;
    if (smooth)
      dense =
          std::make_unique<DenseGeometry>(make_dense_geometry(SmoothCurves(g, 30.0), [&q](Vec2 p) { return q.at(p); }));
    const Geometry& ng = smooth ? dense->geometry : g;
    const NodeSet nodes = place_boundary_nodes(ng, q, BoundaryNodeRule::Spacing, nullptr);
    const double worst = worst_edge_ratio(nodes, ng, q, 8);
    INFO("worst |edge / q(midpoint) - 1| = " << worst);
    CHECK(worst <= 0.10);
    // The input mode on the same geometry is far off: the sides are single segments.
    if (!smooth) CHECK(worst_edge_ratio(make_boundary_nodes(g, q), g, q, 0) > 1.0);
  }
}

TEST_CASE("spacing nodes keep every critical point, lie on the curve and give every section an edge", "[placement]") {
  const Geometry g = plate();
  const ConstantSpacing q(0.4);
  const NodeSet nodes = place_boundary_nodes(g, q, BoundaryNodeRule::Spacing, nullptr);
  const GeometryTree tree(g);
  // Every critical point is a Fixed node at exactly its location, in Geometry::critical order.
  REQUIRE(nodes.count(NodeKind::Fixed) == g.critical.size());
  for (std::size_t k = 0; k < g.critical.size(); ++k) {
    CHECK(nodes.kind[k] == NodeKind::Fixed);
    CHECK(nodes.x[k] == g.critical[k].p);
  }
  for (std::size_t c = 0; c < g.curves.size(); ++c) {
    const Curve& curve = g.curves[c];
    const auto& list = nodes.curve_nodes[c];
    // Each critical vertex appears in the curve's list, with at least one edge to the next one.
    std::size_t pos = 0;
    for (std::size_t i = 0; i < curve.points.size(); ++i) {
      if (!curve.critical[i]) continue;
      while (pos < list.size() && !(nodes.x[static_cast<std::size_t>(list[pos])] == curve.points[i])) ++pos;
      REQUIRE(pos < list.size());
      CHECK(nodes.kind[static_cast<std::size_t>(list[pos])] == NodeKind::Fixed);
    }
    for (std::size_t k = 0; k + 1 < list.size(); ++k) CHECK(list[k] != list[k + 1]);
    for (const int node : list) {
      const double off = tree.closest_on_curve(nodes.x[static_cast<std::size_t>(node)], static_cast<int>(c)).distance;
      CHECK(off <= 1e-12 * 12.0);
    }
  }
  // The 0.1-long curve is one edge; the bump's sides (length 1) two or three edges each, the rest 12 or 13.
  CHECK(nodes.curve_nodes[1].size() == 2);
  CHECK(nodes.curve_nodes[0].size() >= 1 + 12 + 2 + 2);
  // The boundary handler accepts the lists (ordered arcs, Fixed ends).
  const BoundaryHandler handler(tree, nodes);
  for (const auto& arcs : handler.arcs())
    for (std::size_t k = 1; k < arcs.size(); ++k) CHECK(arcs[k - 1] < arcs[k]);
}

TEST_CASE("spacing nodes: no chord strays from the curve by more than 0.1 (q_a + q_b) / 2", "[placement]") {
  // A zig-zag of unit segments whose vertices turn 29 degrees (below the corner angle, so not
  // critical), closed by a polyline with right-angle corners. With q = 1.3 the equal-integral
  // chords straddle vertices near their middle and cut the corners by up to 0.13 q.
  std::vector<Vec2> zig{{0, 0}};
  for (int i = 1; i <= 24; ++i) {
    const double a = (i % 2 ? 1.0 : -1.0) * 14.5 * std::numbers::pi / 180;
    zig.push_back(zig.back() + Vec2{std::cos(a), std::sin(a)});
  }
  const Geometry g = build_geometry(
      {{"zig", zig, "test", 1, {}}, {"close", {zig.back(), {zig.back().x, -3}, {0, -3}, {0, 0}}, "test", 40, {}}});
  const ConstantSpacing q(1.3);
  PlacementOptions options;
  const CurveStations stations = spacing_stations(g, q, options);
  const Curve& curve = g.curves[0];
  const GeometryTree tree(g);
  auto worst_deviation = [&](const CurveStations& st) {
    double worst = 0.0;
    // Arc positions of the stations, as the boundary handler finds them.
    const BoundaryHandler handler(tree, assemble_boundary_nodes(g, q, st));
    const auto& a = handler.arcs()[0];
    for (std::size_t k = 0; k + 1 < a.size(); ++k) worst = std::max(worst, chord_deviation(curve, a[k], a[k + 1]));
    return worst;
  };
  const double rule = options.max_deviation * q.q;
  const double with_rule = worst_deviation(stations);
  INFO("worst chord deviation " << with_rule << ", allowed " << rule);
  CHECK(with_rule <= rule);
  // Without the rule's rounds the equal-integral placement breaks it: the test can fail.
  options.max_rounds = 0;
  CHECK(worst_deviation(spacing_stations(g, q, options)) > rule);
}

TEST_CASE("spacing nodes: a field asking for too many boundary nodes is refused", "[placement]") {
  const Geometry g = plate();
  PlacementOptions options;
  options.max_nodes = 1000;
  CHECK_THROWS_AS(spacing_stations(g, ConstantSpacing(0.01), options), LimitError);
  CHECK_NOTHROW(spacing_stations(g, ConstantSpacing(0.1), options));
  struct Bad final : SpacingField {
    double at(Vec2 p) const override { return p.x > 11 ? -1.0 : 0.5; }
  };
  CHECK_THROWS_AS(spacing_stations(g, Bad{}, {}), LimitError);
}

TEST_CASE("input nodes through the station assembly are the thesis' rule", "[placement]") {
  const Geometry g = plate();
  const WavySpacing q;
  const NodeSet a = make_boundary_nodes(g, q);
  const NodeSet b = place_boundary_nodes(g, q, BoundaryNodeRule::Input, nullptr);
  REQUIRE(a.size() == b.size());
  // Every geometry point is a node, once per location.
  std::size_t points = 0;
  for (const Curve& c : g.curves) points += c.points.size() - 1;  // closed loops: ends shared
  CHECK(a.size() == points);
  for (std::size_t i = 0; i < a.size(); ++i) {
    CHECK(a.x[i] == b.x[i]);
    CHECK(a.kind[i] == b.kind[i]);
  }
  CHECK(a.curve_nodes == b.curve_nodes);
  // The boundary-node spacing per segment is then the segment length, and with it given
  // explicitly the initialization tree is the thesis' one.
  const GeometryTree tree(g);
  const std::vector<double> lengths = station_resolution(g, vertex_stations(g));
  REQUIRE(lengths.size() == g.segments.size());
  for (std::size_t k = 0; k < lengths.size(); ++k) CHECK(lengths[k] == g.segments[k].length);
  InitOptions plain{InitMethod::Random, 5, {}};
  InitOptions given = plain;
  given.segment_resolution = &lengths;
  const InitialDistribution d1 = make_initial_distribution(tree, q, plain);
  const InitialDistribution d2 = make_initial_distribution(tree, q, given);
  REQUIRE(d1.nodes.size() == d2.nodes.size());
  for (std::size_t i = 0; i < d1.nodes.size(); ++i) CHECK(d1.nodes.x[i] == d2.nodes.x[i]);
  CHECK(d1.estimate == d2.estimate);
}

TEST_CASE(
    "spacing nodes on smooth curves: the fill matches the estimate and a short run keeps "
    "boundary nodes on the smooth curve",
    "[placement][smooth]") {
  // A coarsely segmented circle (16 points, radius 3) in a square.
  const RawCurve hole = fixtures::circle_curve(3.0, 16, 0.0, "hole");
  const Geometry g = build_geometry({{"box", {{-5, -5}, {5, -5}, {5, 5}, {-5, 5}, {-5, -5}}, "test", 1, {}}, hole});
  const ConstantSpacing q(0.5);
  const SmoothCurves smooth(g, 30.0);
  const DenseGeometry dense = make_dense_geometry(smooth, [&q](Vec2 p) { return q.at(p); });
  const GeometryTree tree(dense.geometry);
  const CurveStations stations = spacing_stations(dense.geometry, q);
  const NodeSet boundary = assemble_boundary_nodes(dense.geometry, q, stations);
  const std::vector<double> resolution = station_resolution(dense.geometry, stations);
  // Every dense segment lies under a boundary edge of about q.
  for (const double r : resolution) CHECK(std::fabs(r / 0.5 - 1.0) < 0.1);
  InitOptions init{InitMethod::Structured, 1, {}};
  init.boundary = &boundary;
  init.segment_resolution = &resolution;
  const InitialDistribution d = make_initial_distribution(tree, q, init);
  INFO("nodes " << d.nodes.size() << ", estimate " << d.estimate);
  // docs/initialization.md: the structured fill lands within about 0.8 to 1.3 of the estimate.
  CHECK(d.nodes.size() > 0.8 * d.estimate);
  CHECK(d.nodes.size() < 1.3 * d.estimate);

  NodeSet nodes = d.nodes;
  SimOptions options;
  options.iterations = 40;
  options.dt_initial = 0.01;
  options.quiet = true;
  const SimResult result = run_simulation(nodes, tree, q, options, {});
  CHECK(result.state.iterations_done == 40);
  // Boundary nodes: on the dense polyline up to rounding, hence within its chord tolerance of the
  // smooth curve; interior nodes inside.
  const double tol = DenseOptions{}.tolerance * 0.5;
  double worst_dense = 0.0, worst_smooth = 0.0;
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    if (nodes.kind[i] == NodeKind::Interior) {
      CHECK(tree.inside(nodes.x[i]));
      continue;
    }
    worst_dense = std::max(worst_dense, tree.closest_on_curve(nodes.x[i], nodes.curve[i]).distance);
    if (nodes.curve[i] == 1) worst_smooth = std::max(worst_smooth, std::fabs(norm(nodes.x[i]) - 3.0));
  }
  INFO("boundary nodes off the dense curve by " << worst_dense << ", off the circle by " << worst_smooth);
  CHECK(worst_dense <= 1e-12 * 5.0);
  // Off the circle: the spline's own error (0.029 of the 16-gon's chord error 0.058, test_smooth_curve)
  // plus the dense tolerance.
  CHECK(worst_smooth <= 0.03 * 3.0 * (1.0 - std::cos(std::numbers::pi / 16)) + tol);
  CHECK(nodes.count(NodeKind::Boundary) > 0);
}

namespace {

void write_crv(const std::filesystem::path& file, const std::vector<std::vector<Vec2>>& curves) {
  std::ofstream out(file);
  out.precision(17);
  for (const auto& c : curves) {
    out << c.size() << "\n";
    for (const Vec2 p : c) out << p.x << " " << p.y << "\n";
  }
}

}  // namespace

TEST_CASE("pdmesh mesh: smooth curves with spacing nodes pass --check, and crossing smooth curves fall back",
          "[placement][smooth][cli]") {
  const auto dir = pdmesh_test::fresh_dir("boundary_modes");
  // A 16-point circle of radius 1 in a box with one point per corner: both far coarser than q = 0.1.
  const RawCurve hole = fixtures::circle_curve(1.0, 16, 0.0, "hole");
  write_crv(dir / "coarse.crv", {{{-2, -2}, {2, -2}, {2, 2}, {-2, 2}, {-2, -2}}, hole.points});
  const auto r =
      pdmesh_test::run_pdmesh("mesh '" + (dir / "coarse.crv").string() + "' --out '" + (dir / "out").string() +
                              "' --iterations 20 --device host --check --formats msh "
                              "--set spacing.expression=0.1 --set geometry.curves=smooth");
  INFO(r.output);
  REQUIRE(r.status == 0);
  CHECK_THAT(r.output, Catch::Contains("smooth curves (centripetal Catmull-Rom) as a dense polyline"));
  CHECK_THAT(r.output, Catch::Contains("mesh check (triangulation): passed"));
  CHECK_THAT(r.output, Catch::Contains("mesh check (cleaned mesh): passed"));
  // The best preset placed the boundary nodes by the field it relaxes at (spacing.relax_scale 1.09 x
  // 0.1): about 2 pi / 0.109 = 58 on the circle and 4 / 0.109 = 37 a side on the box, where the input
  // gives 16 + 4.
  const NodeFile initial = read_node_file(dir / "out" / "initial.nodes");
  const std::size_t on_boundary = initial.nodes.count(NodeKind::Boundary) + initial.nodes.count(NodeKind::Fixed);
  CHECK(on_boundary >= 58 + 148 - 4);
  CHECK(on_boundary <= 58 + 148 + 4);

  // Two coarse curves whose smooth versions cross (test_smooth_curve.cpp): a note, then polylines.
  const RawCurve hole16 = fixtures::circle_curve(1.0, 16, std::numbers::pi / 16, "hole");
  write_crv(dir / "crossing.crv", {{{-2, -2}, {0.99, -2}, {0.99, 2}, {-2, 2}, {-2, -2}}, hole16.points});
  const auto f =
      pdmesh_test::run_pdmesh("mesh '" + (dir / "crossing.crv").string() + "' --out '" + (dir / "out2").string() +
                              "' --iterations 5 --device host --check --formats msh --set geometry.curves=smooth");
  INFO(f.output);
  CHECK(f.status == 0);
  CHECK_THAT(f.output, Catch::Contains("note: geometry.curves = \"smooth\" fell back to the input polylines"));
  std::filesystem::remove_all(dir);
}

TEST_CASE("MeshInputs: the spacing field reads the input segments, everything else the node geometry",
          "[placement][smooth]") {
  const auto dir = pdmesh_test::fresh_dir("mesh_inputs");
  const RawCurve hole = fixtures::circle_curve(1.0, 16, 0.0, "hole");
  write_crv(dir / "coarse.crv", {{{-2, -2}, {2, -2}, {2, 2}, {-2, 2}, {-2, -2}}, hole.points});
  const CaseConfig smooth = case_for_geometry_file(dir / "coarse.crv", {parse_set_option("geometry.curves=smooth")});
  const MeshInputs inputs(smooth);
  REQUIRE(inputs.dense);
  CHECK(inputs.geometry.segments.size() == 4 + 16);
  CHECK(&inputs.tree->geometry() == &inputs.geometry);
  CHECK(&inputs.node_tree().geometry() == &inputs.dense->geometry);
  CHECK(inputs.node_geometry().segments.size() > 4 + 16);
  // Eq. 3.6 on the input polyline: on a hole segment q is that segment's length (0.39), where a
  // field over the dense polyline would give its much shorter segments.
  const Vec2 mid = 0.5 * (hole.points[0] + hole.points[1]);
  CHECK(inputs.spacing->at(mid) == Approx(dist(hole.points[0], hole.points[1])));
  // Boundary nodes (best preset: spacing) lie on the dense polyline, and the initial distribution
  // starts from them.
  const SpacingStage spacing(smooth, inputs);
  const BoundaryPlacement placed = place_boundary(smooth, inputs, spacing);
  REQUIRE(placed.nodes);
  const NodeSet* boundary = &*placed.nodes;
  for (std::size_t i = 0; i < boundary->size(); ++i)
    CHECK(inputs.node_tree().closest_on_curve(boundary->x[i], boundary->curve[i]).distance < 1e-12);
  const InitialDistribution initial = make_initial(smooth, inputs, spacing);
  for (std::size_t i = 0; i < boundary->size(); ++i) CHECK(initial.nodes.x[i] == boundary->x[i]);
  // The thesis preset: one geometry, no placement of its own.
  const CaseConfig thesis = case_for_geometry_file(dir / "coarse.crv", {parse_set_option("preset=thesis")});
  const MeshInputs plain(thesis);
  CHECK_FALSE(plain.dense);
  CHECK(&plain.node_tree() == plain.tree.get());
  const BoundaryPlacement none = place_boundary(thesis, plain, SpacingStage(thesis, plain));
  CHECK_FALSE(none.nodes);
  CHECK(none.resolution.empty());
  std::filesystem::remove_all(dir);
}
