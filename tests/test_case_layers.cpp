// Tests of [[boundary_layer]] (docs/boundary-layers.md): the case tables read and range-checked, and
// a run with layers: unknown curves refused before anything is written, the merged mixed mesh.
#include <catch2/catch.hpp>
#include <fmt/format.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <sstream>
#include <string>

#include "app/config/case_file.hpp"
#include "app/pipeline/layer_pipeline.hpp"
#include "app/pipeline/mesh_pipeline.hpp"
#include "core/errors.hpp"
#include "temp_files.hpp"

namespace fs = std::filesystem;
using namespace pdmesh;

namespace {

const fs::path kCase = "/cases/demo/case.toml";
const std::string kGeometry = "[geometry]\nfiles = [\"a.crv\"]\ncurve_names = [\"wall\", \"far\"]\n";

std::string error_of(const std::string& text) {
  try {
    parse_case_text(text, kCase);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

std::string layer(const std::string& body) { return kGeometry + "[[boundary_layer]]\n" + body; }

std::string read(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// A circle of radius 0.5 (the wall) inside a square of side 4.
std::vector<RawCurve> circle_in_square() {
  RawCurve wall{"wall", {}, "memory", 1, {}};
  const int n = 64;
  for (int k = 0; k <= n; ++k) {
    const double a = 2.0 * std::numbers::pi * (k % n) / n;
    wall.points.push_back({0.5 * std::cos(a), 0.5 * std::sin(a)});
  }
  RawCurve far{"far", {{-2, -2}, {2, -2}, {2, 2}, {-2, 2}, {-2, -2}}, "memory", 1, {}};
  return {far, wall};
}

CaseConfig layered_case(const fs::path& out, const std::string& wall_name, bool quads) {
  CaseConfig c =
      case_for_curves(circle_in_square(), "circle",
                      {parse_set_option("simulation.iterations=60"), parse_set_option("simulation.device=host"),
                       parse_set_option("output.formats=[\"msh\",\"vtu\",\"su2\"]")});
  CaseConfig::BoundaryLayer b;
  b.curves = {wall_name};
  b.first_height = 1e-3;
  b.growth = 1.2;
  b.thickness = 0.05;
  b.quads = quads;
  c.boundary_layers.push_back(b);
  c.out_dir = out;
  c.quiet = true;
  return c;
}

}  // namespace

TEST_CASE("[[boundary_layer]] tables are read into CaseConfig", "[app][case][layers]") {
  const CaseConfig c = parse_case_text(layer("curves = [\"wall\"]\nfirst_height = 1e-5\ngrowth = 1.15\n"
                                             "thickness = 0.02\nelements = \"quads\"\n") +
                                           "[[boundary_layer]]\ncurves = [\"far\"]\nfirst_height = 0.001\nlayers = 4\n",
                                       kCase);
  REQUIRE(c.boundary_layers.size() == 2);
  const auto& a = c.boundary_layers[0];
  CHECK(a.curves == std::vector<std::string>{"wall"});
  CHECK(a.first_height == 1e-5);
  CHECK(a.growth == 1.15);
  CHECK(a.thickness == 0.02);
  CHECK(a.layers == 0);
  CHECK(a.quads);
  // Where the curves were given (line 5, the value's column), for the errors of names only the
  // geometry files can check.
  CHECK(a.curves_where == kCase.string() + ":5:10");
  const auto& b = c.boundary_layers[1];
  CHECK(b.layers == 4);
  CHECK(b.thickness == 0.0);
  CHECK(b.growth == 1.2);  // the default
  CHECK_FALSE(b.quads);    // triangles by default
  // Without the section: none.
  CHECK(parse_case_text(kGeometry, kCase).boundary_layers.empty());
  // A single [boundary_layer] table is one section.
  CHECK(parse_case_text(kGeometry + "[boundary_layer]\ncurves = [\"wall\"]\nfirst_height = 1e-5\nthickness = 0.1\n",
                        kCase)
            .boundary_layers.size() == 1);
}

TEST_CASE("[[boundary_layer]] y_plus gives White's flat-plate first height", "[app][case][layers]") {
  const CaseConfig c = parse_case_text(
      layer("curves = [\"wall\"]\ny_plus = 1\nreynolds = 9e6\nreference_length = 1\nthickness = 0.02\n"), kCase);
  REQUIRE(c.boundary_layers.size() == 1);
  // Cf = 0.026 / (9e6)^(1/7) = 0.002637; y = 1 / (9e6 sqrt(Cf / 2)) = 3.06e-6.
  const double cf = 0.026 / std::pow(9e6, 1.0 / 7.0);
  CHECK(c.boundary_layers[0].first_height == Approx(1.0 / (9e6 * std::sqrt(cf / 2))).epsilon(1e-12));
  CHECK(c.boundary_layers[0].first_height == Approx(3.06e-6).epsilon(0.01));
  CHECK(first_height_for_y_plus(2.0, 9e6, 0.5) == Approx(c.boundary_layers[0].first_height).epsilon(1e-12));
}

TEST_CASE("bad [[boundary_layer]] settings are input errors naming the key and the value", "[app][case][layers]") {
  const std::string ok_tail = "first_height = 1e-5\nthickness = 0.05\n";
  CHECK_THAT(error_of(layer("curves = [\"wing\"]\n" + ok_tail)),
             Catch::Contains("boundary_layer.curves") && Catch::Contains("'wing'") && Catch::Contains(":5:"));
  CHECK_THAT(error_of(layer("curves = [\"wall\"]\ngrowth = 1.0\n" + ok_tail)),
             Catch::Contains("boundary_layer.growth must be in (1, 3], got 1"));
  CHECK_THAT(error_of(layer("curves = [\"wall\"]\ngrowth = 0.9\n" + ok_tail)), Catch::Contains("got 0.9"));
  CHECK_THAT(error_of(layer("curves = [\"wall\"]\nfirst_height = 0.1\nthickness = 0.05\n")),
             Catch::Contains("first_height 0.1 is above boundary_layer.thickness 0.05"));
  CHECK_THAT(error_of(layer("curves = [\"wall\"]\ngrwth = 1.2\n" + ok_tail)),
             Catch::Contains("unknown key 'boundary_layer.grwth'; did you mean 'boundary_layer.growth'?"));
  CHECK_THAT(error_of(layer("curves = [\"wall\"]\nfirst_height = -1\nthickness = 0.05\n")),
             Catch::Contains("boundary_layer.first_height must be > 0, got -1"));
  CHECK_THAT(error_of(layer("curves = [\"wall\"]\nfirst_height = 1e-5\n")),
             Catch::Contains("exactly one of thickness and layers"));
  CHECK_THAT(error_of(layer("curves = [\"wall\"]\nfirst_height = 1e-5\nthickness = 0.1\nlayers = 3\n")),
             Catch::Contains("exactly one of thickness and layers"));
  CHECK_THAT(error_of(layer("curves = [\"wall\"]\nthickness = 0.1\n")), Catch::Contains("first_height and y_plus"));
  CHECK_THAT(error_of(layer("curves = [\"wall\"]\ny_plus = 1\nthickness = 0.1\n")),
             Catch::Contains("boundary_layer.reynolds is required"));
  CHECK_THAT(error_of(layer("curves = [\"wall\"]\n" + ok_tail + "elements = \"hexes\"\n")),
             Catch::Contains("boundary_layer.elements must be one of triangles, quads, got 'hexes'"));
  CHECK_THAT(error_of(layer("curves = []\n" + ok_tail)), Catch::Contains("at least one curve"));
  CHECK_THAT(error_of(layer("curves = [\"wall\"]\n" + ok_tail) + "[[boundary_layer]]\ncurves = [\"wall\"]\n" + ok_tail),
             Catch::Contains("curve 'wall' is in two [[boundary_layer]] tables"));
  CHECK_THAT(error_of("boundary_layer = 3\n" + kGeometry), Catch::Contains("boundary_layer must be a table"));
}

TEST_CASE("a run with an unknown layer curve writes nothing", "[app][layers]") {
  const fs::path out = pdmesh_test::fresh_path("layers_unknown");
  fs::remove_all(out);
  CaseConfig c = layered_case(out, "wing", true);
  c.boundary_layers[0].curves_where = "demo.toml:7:10";
  CHECK_THROWS_WITH(run_mesh(c), Catch::StartsWith("demo.toml:7:10: boundary_layer.curves: unknown curve 'wing' "
                                                   "(the geometry's curves: far, wall)"));
  CHECK_FALSE(fs::exists(out));
}

TEST_CASE("a layered run refuses every mesh format that cannot hold quads, before writing", "[app][layers]") {
  for (const char* format : {"msh22", "triangle", "fort14", "2dm"}) {
    INFO(format);
    const fs::path out = pdmesh_test::fresh_path("layers_format");
    fs::remove_all(out);
    CaseConfig c = layered_case(out, "wall", true);
    c.output.formats = {"msh", format, "png"};
    CHECK_THROWS_WITH(run_mesh(c),
                      Catch::Contains(fmt::format("output.formats: '{}' cannot hold the cells of "
                                                  "[[boundary_layer]] (msh, vtu, su2, mesh, openfoam, cgns can)",
                                                  format)));
    CHECK_FALSE(fs::exists(out));
  }
}

TEST_CASE("a run whose wall chain is open meshes the layer up to the curves that continue it", "[app][layers]") {
  // The circle cut into an upper and a lower half; layers on the upper half only: the chain's ends
  // continue along "lower", in line with the wall, so the front runs up the end rays.
  std::vector<RawCurve> curves = circle_in_square();
  RawCurve upper{"upper", {}, "memory", 1, {}}, lower{"lower", {}, "memory", 1, {}};
  const std::vector<Vec2>& circle = curves[1].points;
  for (std::size_t k = 0; k < circle.size(); ++k) {
    if (k <= circle.size() / 2) upper.points.push_back(circle[k]);
    if (k >= circle.size() / 2) lower.points.push_back(circle[k]);
  }
  CaseConfig c =
      case_for_curves({curves[0], upper, lower}, "halves",
                      {parse_set_option("simulation.iterations=60"), parse_set_option("simulation.device=host"),
                       parse_set_option("output.formats=[\"msh\",\"su2\"]")});
  CaseConfig::BoundaryLayer b;
  b.curves = {"upper"};
  b.first_height = 1e-3;
  b.growth = 1.2;
  b.thickness = 0.05;
  c.boundary_layers.push_back(b);
  const fs::path out = pdmesh_test::fresh_path("layers_open");
  fs::remove_all(out);
  c.out_dir = out;
  c.quiet = true;
  REQUIRE(run_mesh(c) == 0);
  const std::string json = read(out / "quality.json");
  CHECK_THAT(json, Catch::Contains("\"inverted_cells\": 0") && Catch::Contains("\"first_height_within_2pct\": 1"));
  // The core meets the end columns (their edges the layers' heights, from 1e-3 at the wall) at their
  // length: no core node fans out to their nodes in slivers.
  const auto at = json.find("\"core_min_angle\": ");
  REQUIRE(at != std::string::npos);
  CHECK(std::stod(json.substr(at + 18)) >= 30.0);
  // One marker per curve, the wall's and the lower half's edges in them.
  const std::string su2 = read(out / "mesh.su2");
  CHECK_THAT(su2, Catch::Contains("MARKER_TAG= upper\nMARKER_ELEMS= ") &&
                      Catch::Contains("MARKER_TAG= lower\nMARKER_ELEMS= "));
  CHECK_THAT(su2, !Catch::Contains("MARKER_ELEMS= 0\n"));
  fs::remove_all(out);
}

TEST_CASE("a channel with layers on its walls: the inlet and outlet hold the layers' sides", "[app][layers]") {
  // A channel [0,2] x [0,1], walls bottom and top, inlet and outlet of 4 segments each: the end rays
  // run along the inlet and outlet, whose markers then hold the layer's side edges and the core's.
  const auto line = [](Vec2 a, Vec2 b, int n) {
    std::vector<Vec2> p;
    for (int i = 0; i <= n; ++i) p.push_back(a + (b - a) * (static_cast<double>(i) / n));
    return p;
  };
  const std::vector<RawCurve> curves{{"bottom", line({0, 0}, {2, 0}, 40), "memory", 1, {}},
                                     {"outlet", line({2, 0}, {2, 1}, 4), "memory", 1, {}},
                                     {"top", line({2, 1}, {0, 1}, 40), "memory", 1, {}},
                                     {"inlet", line({0, 1}, {0, 0}, 4), "memory", 1, {}}};
  CaseConfig c =
      case_for_curves(curves, "channel",
                      {parse_set_option("simulation.iterations=60"), parse_set_option("simulation.device=host"),
                       parse_set_option("output.formats=[\"msh\",\"su2\"]")});
  CaseConfig::BoundaryLayer b;
  b.curves = {"bottom", "top"};
  b.first_height = 2e-3;
  b.growth = 1.2;
  b.thickness = 0.1;
  b.quads = true;
  c.boundary_layers.push_back(b);
  const fs::path out = pdmesh_test::fresh_path("layers_channel");
  fs::remove_all(out);
  c.out_dir = out;
  c.quiet = true;
  REQUIRE(run_mesh(c) == 0);
  const std::string json = read(out / "quality.json");
  CHECK_THAT(json, Catch::Contains("\"inverted_cells\": 0") && Catch::Contains("\"first_height_within_2pct\": 1"));
  // The inlet's marker: from (0, 0) to (0, 1) without a gap, the two layers' sides and the core's
  // edges between them; their lengths add up to the inlet's.
  const std::string su2 = read(out / "mesh.su2");
  std::vector<Vec2> points;
  {
    std::istringstream in(su2.substr(su2.find("NPOIN=")));
    std::string key;
    std::size_t n = 0;
    in >> key >> n;
    for (std::size_t i = 0; i < n; ++i) {
      double x = 0, y = 0;
      std::size_t id = 0;
      in >> x >> y >> id;
      points.push_back({x, y});
    }
  }
  for (const std::string name : {"inlet", "outlet"}) {
    std::istringstream in(su2.substr(su2.find("MARKER_TAG= " + name)));
    std::string key, tag;
    std::size_t n = 0;
    in >> key >> tag >> key >> n;
    double length = 0.0;
    std::size_t side = 0;  // edges below y = 0.1 or above 0.9: the layers'
    for (std::size_t i = 0; i < n; ++i) {
      int type = 0;
      std::size_t a = 0, e = 0;
      in >> type >> a >> e;
      CHECK(points[a].x == Approx(name == "inlet" ? 0.0 : 2.0).margin(1e-12));
      CHECK(points[e].x == Approx(name == "inlet" ? 0.0 : 2.0).margin(1e-12));
      length += dist(points[a], points[e]);
      if (std::max(points[a].y, points[e].y) <= 0.1 + 1e-9 || std::min(points[a].y, points[e].y) >= 0.9 - 1e-9) ++side;
    }
    CHECK(length == Approx(1.0).epsilon(1e-9));
    CHECK(side >= 2 * 10);  // both layers' columns: at least 10 layers each (h1 2e-3, growth 1.2, 0.1)
  }
  fs::remove_all(out);
}

TEST_CASE("a run with layers writes one mesh of layer quads and core triangles", "[app][layers]") {
  const fs::path out = pdmesh_test::fresh_path("layers_run");
  fs::remove_all(out);
  REQUIRE(run_mesh(layered_case(out, "wall", true)) == 0);
  const std::string msh = read(out / "mesh.msh");
  CHECK_THAT(msh, Catch::Contains("\"boundary_layer\""));
  CHECK_THAT(msh, Catch::Contains("\n2 2 3 "));  // a block of quadrangles (type 3) in the layer's surface
  CHECK_THAT(msh, Catch::Contains("\n2 1 2 "));  // the core's triangles
  CHECK_THAT(read(out / "mesh.su2"), Catch::Contains("\n9 "));  // SU2 quadrilateral
  CHECK_THAT(read(out / "mesh.su2"), Catch::Contains("MARKER_TAG= wall"));
  CHECK_THAT(read(out / "mesh.vtu"), Catch::Contains("\n9\n"));
  const std::string json = read(out / "quality.json");
  CHECK_THAT(json, Catch::Contains("\"boundary_layer\"") && Catch::Contains("\"first_height_within_2pct\": 1"));
  fs::remove_all(out);
  // Triangles: no quadrangle anywhere.
  REQUIRE(run_mesh(layered_case(out, "wall", false)) == 0);
  CHECK_THAT(read(out / "mesh.msh"), !Catch::Contains("\n2 2 3 ") && Catch::Contains("\n2 2 2 "));
  fs::remove_all(out);
}

TEST_CASE("a layered run draws its mesh pictures on the background thread", "[app][layers]") {
  const fs::path out = pdmesh_test::fresh_path("layers_pictures");
  CaseConfig c = layered_case(out, "wall", true);
  c.output.formats = {"msh", "png"};
  ViewWindow view;
  view.name = "wall";
  view.window.add({0.4, -0.1});
  view.window.add({0.6, 0.1});
  c.output.views = {view};
  c.timings_file = out.string() + ".timings.json";
  pdmesh_test::temp_paths().add(*c.timings_file);
  REQUIRE(run_mesh(c) == 0);
  CHECK(fs::file_size(out / "mesh.png") > 0);
  CHECK(fs::file_size(out / "mesh_wall.png") > 0);
  // Queued as the run's other pictures are (one background job each, waited for at the end), not
  // drawn in one phase of the run's own thread.
  const std::string timings = read(*c.timings_file);
  CHECK_THAT(timings, Catch::Contains("{\"name\": \"mesh.png\"") && Catch::Contains("\"waiting for pictures\""));
  CHECK_THAT(timings, !Catch::Contains("\"mesh pictures\""));
  const auto job = timings.find("{\"name\": \"mesh_wall.png\"");
  REQUIRE(job != std::string::npos);
  CHECK_THAT(timings.substr(job, timings.find('}', job) - job), Catch::Contains("\"background\": true"));
}

TEST_CASE("nodes the simulation snapped onto a layer front are left out of the core", "[app][layers]") {
  // A front (fixed points) and a plain curve; node 3 was snapped onto the front between its points.
  RawCurve far{"far", {{-2, -2}, {2, -2}, {2, 2}, {-2, 2}, {-2, -2}}, "memory", 1, {}};
  RawCurve front{"wall_front", {{-0.5, -0.5}, {0.5, -0.5}, {0.5, 0.5}, {-0.5, 0.5}, {-0.5, -0.5}}, "memory", 1, {},
                 true};
  const Geometry g = build_geometry({far, front});
  NodeSet nodes;
  const int f0 = nodes.add({-2, -2}, 0.1, NodeKind::Fixed, 0);
  const int b0 = nodes.add({0, -2}, 0.1, NodeKind::Boundary, 0);
  const int w0 = nodes.add({-0.5, -0.5}, 0.1, NodeKind::Fixed, 1);
  const int snapped = nodes.add({0, -0.5}, 0.1, NodeKind::Boundary, 1);
  const int w1 = nodes.add({0.5, -0.5}, 0.1, NodeKind::Fixed, 1);
  const int inner = nodes.add({1, 1}, 0.1, NodeKind::Interior, -1);
  nodes.curve_nodes = {{f0, b0, f0}, {w0, snapped, w1, w0}};
  std::size_t dropped = 0;
  const NodeSet out = without_front_nodes(nodes, g, dropped);
  CHECK(dropped == 1);
  REQUIRE(out.size() == 5);
  CHECK(out.curve_nodes[0] == std::vector<int>{0, 1, 0});  // the plain curve's boundary node stays
  CHECK(out.curve_nodes[1] == std::vector<int>{2, 3, 2});  // the front: its fixed nodes only
  CHECK(out.x[3] == Vec2{0.5, -0.5});
  CHECK(out.kind[4] == NodeKind::Interior);
  (void)inner;
}

TEST_CASE("the stages driven directly refuse a case with layers", "[app][layers]") {
  // A caller driving the stages (as the Python Mesher does) must run them on the core's case.
  const CaseConfig c = layered_case(pdmesh_test::fresh_path("layers_stages"), "wall", true);
  const MeshInputs inputs(c);
  const SpacingStage spacing(c, inputs);
  CHECK_THROWS_WITH(make_initial(c, inputs, spacing), Catch::Contains("the stages mesh the core's case"));
}

TEST_CASE("the core's spacing at a front node is at least 0.8 of its longest front edge", "[app][layers]") {
  // The circle's last layer (about 0.008) is far below its front edges (about 0.054): the core must
  // not be sized by the last layer alone there, or it meets those edges with flat triangles.
  const CaseConfig c = layered_case(pdmesh_test::fresh_path("layers_front"), "wall", true);
  const MeshInputs inputs(c);
  const SpacingStage spacing(c, inputs);
  const auto layered = build_layers(c, inputs, spacing);
  const LayerMesh& m = layered->sections.at(0).mesh;
  const LayerFront& f = m.fronts.at(0);
  REQUIRE(f.closed);
  const std::size_t n = f.nodes.size();
  for (std::size_t k = 0; k < n; ++k) {
    const Vec2 p = m.nodes[f.nodes[k]];
    const double longest = std::max(dist(p, m.nodes[f.nodes[(k + 1) % n]]), dist(p, m.nodes[f.nodes[(k + n - 1) % n]]));
    CHECK(layered->core.spacing.given->at(p) >= std::min(spacing.field().at(p), 0.8 * longest) - 1e-12);
  }
}

TEST_CASE("the core's field lowered at the fronts gives at()'s values in batches", "[app][layers]") {
  // The core's inputs sample it with at_many (on several threads): every value must be at()'s.
  const CaseConfig c = layered_case(pdmesh_test::fresh_path("layers_front_batch"), "wall", true);
  const MeshInputs inputs(c);
  const SpacingStage spacing(c, inputs);
  const auto layered = build_layers(c, inputs, spacing);
  const SpacingField& field = *layered->core.spacing.given;
  std::vector<Vec2> points;
  for (int i = 0; i <= 150; ++i)
    for (int j = 0; j <= 150; ++j) points.push_back({-2.0 + 4.0 * i / 150, -2.0 + 4.0 * j / 150});
  for (const Vec2 p : layered->sections.at(0).mesh.nodes) points.push_back(p);
  std::vector<double> q;
  field.at_many(points, q);
  REQUIRE(q.size() == points.size());
  std::size_t lowered = 0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    REQUIRE(q[i] == field.at(points[i]));  // bit for bit
    lowered += q[i] < spacing.asked().at(points[i]);
  }
  CHECK(lowered > 1000);  // the fronts' sources lower the case's field near the wall
}

TEST_CASE("triangles keep the rays within 5 degrees of their walls' normals, quads do not", "[app][layers]") {
  // A split wall cell has an angle of 90 degrees + its ray's tilt from the segment's normal
  // (LayerSettings::max_ray_tilt_deg); quads keep the smoothed rays as they are.
  for (const bool quads : {false, true}) {
    const CaseConfig c = layered_case(pdmesh_test::fresh_path("layers_tilt"), "wall", quads);
    const MeshInputs inputs(c);
    const SpacingStage spacing(c, inputs);
    const auto layered = build_layers(c, inputs, spacing);
    const LayerSection& s = layered->sections.at(0);
    CHECK(s.settings.split_quads == !quads);
    CHECK(s.settings.max_ray_tilt_deg == (quads ? 0.0 : 5.0));
  }
}

TEST_CASE("a narrow wedge with layers on both walls: the core keeps about the angles it has without layers",
          "[app][layers]") {
  // A 15-degree wedge (walls of 30 segments) closed by a mouth without layers. The two walls'
  // layers collide along the wedge; where the gap is narrower than the fronts' edges leave room for,
  // the layer ends on a stair, so the core there meets the walls as it would without layers
  // instead of filling a strip between the fronts, narrower than their edges, with slivers.
  const double angle = 15.0 * std::numbers::pi / 180.0;
  const int n = 30;
  RawCurve lower{"lower", {}, "memory", 1, {}}, upper{"upper", {}, "memory", 1, {}};
  for (int i = 0; i <= n; ++i) lower.points.push_back({static_cast<double>(i) / n, 0.0});
  for (int i = n; i >= 0; --i) upper.points.push_back({std::cos(angle) * i / n, std::sin(angle) * i / n});
  const RawCurve mouth{"mouth", {{1.0, 0.0}, {std::cos(angle), std::sin(angle)}}, "memory", 1, {}};
  const auto min_angle = [](const std::string& json, const std::string& key) {
    const auto at = json.find("\"" + key + "\"");
    REQUIRE(at != std::string::npos);
    const auto colon = json.find(':', at);
    return std::stod(json.substr(colon + 1));
  };
  double plain = 0.0, layered = 0.0;
  for (const bool layers : {false, true}) {
    CaseConfig c =
        case_for_curves({lower, mouth, upper}, "wedge",
                        {parse_set_option("simulation.iterations=60"), parse_set_option("simulation.device=host"),
                         parse_set_option("output.formats=[\"msh\"]")});
    if (layers) {
      CaseConfig::BoundaryLayer b;
      b.curves = {"lower", "upper"};
      b.first_height = 1e-3;
      b.growth = 1.2;
      b.thickness = 0.04;
      c.boundary_layers.push_back(b);
    }
    const fs::path out = pdmesh_test::fresh_path(layers ? "layers_wedge" : "layers_wedge_plain");
    fs::remove_all(out);
    c.out_dir = out;
    c.quiet = true;
    REQUIRE(run_mesh(c) == 0);
    const std::string json = read(out / "quality.json");
    if (layers) {
      CHECK_THAT(json, Catch::Contains("\"inverted_cells\": 0") && Catch::Contains("\"first_height_within_2pct\": 1"));
      layered = min_angle(json, "core_min_angle");
    } else {
      plain = min_angle(json.substr(json.find("\"included_angle\"")), "min");
    }
    fs::remove_all(out);
  }
  INFO("core min angle without layers " << plain << ", with layers " << layered);
  CHECK(layered >= plain - 2.5);
}
