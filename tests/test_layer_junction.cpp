// The junction of the layers and the core (docs/boundary-layers.md, "The junction"): fans whose top
// edges match the core's spacing, columns that merge where the rays are dense, the wall refined
// where they diverge, and a layered NACA 0012 run whose core triangles on the front are well shaped.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "app/config/case_file.hpp"
#include "app/pipeline/layer_pipeline.hpp"
#include "app/pipeline/mesh_pipeline.hpp"
#include "core/predicates.hpp"
#include "geometry/geometry.hpp"
#include "layers/boundary_layers.hpp"
#include "layers/layer_measures.hpp"
#include "quality_json.hpp"
#include "source_dir.hpp"
#include "temp_files.hpp"

namespace fs = std::filesystem;
using namespace pdmesh;
using pdmesh_test::read_quality_json;

namespace {

const double kPi = std::acos(-1.0);

RawCurve circle(double r, int n, const std::string& name) {
  RawCurve curve{name, {}, "test", 1, {}};
  for (int i = 0; i < n; ++i) curve.points.push_back({r * std::cos(2 * kPi * i / n), r * std::sin(2 * kPi * i / n)});
  curve.points.push_back(curve.points.front());
  return curve;
}

RawCurve square(double half, const std::string& name) {
  return {name, {{-half, -half}, {half, -half}, {half, half}, {-half, half}, {-half, -half}}, "test", 1, {}};
}

// Layers of a whole stack (the last layer is the stack's, not a thinner remainder).
LayerSettings settings(double h1, double g, int layers) {
  LayerSettings s;
  s.first_height = h1;
  s.growth = g;
  s.layers = layers;
  return s;
}

// Per front edge: its length over the mean last layer height of the rays whose tops are its ends.
std::vector<double> front_edges_over_last_layer(const LayerMesh& m) {
  std::vector<double> last(m.nodes.size(), 0.0);
  for (const LayerRay& r : m.rays)
    if (r.nodes.size() >= 2 && !r.merged)
      last[r.nodes.back()] = r.correction * dist(m.nodes[r.nodes.back()], m.nodes[r.nodes[r.nodes.size() - 2]]);
  std::vector<double> out;
  for (const LayerFront& f : m.fronts)
    for (std::size_t i = 0; i < f.nodes.size(); ++i) {
      const int a = f.nodes[i], b = f.nodes[(i + 1) % f.nodes.size()];
      REQUIRE(last[a] > 0.0);
      REQUIRE(last[b] > 0.0);
      out.push_back(dist(m.nodes[a], m.nodes[b]) / (0.5 * (last[a] + last[b])));
    }
  return out;
}

double polygon_area(const std::vector<Vec2>& p) {
  double a = 0.0;
  for (std::size_t i = 0; i < p.size(); ++i) a += cross(p[i], p[(i + 1) % p.size()]);
  return 0.5 * a;
}

// The cells' area; with no inverted cell it equals the region between the wall and the front only
// when they tile it (no overlap, no hole).
double cell_area(const LayerMesh& m) {
  double a = 0.0;
  for (const LayerCell& c : m.cells) {
    std::vector<Vec2> p;
    for (int k = 0; k < (c.triangle() ? 3 : 4); ++k) p.push_back(m.nodes[c.v[k]]);
    a += polygon_area(p);
  }
  return a;
}

double front_area(const LayerMesh& m) {
  std::vector<Vec2> p;
  for (const int n : m.fronts.at(0).nodes) p.push_back(m.nodes[n]);
  return polygon_area(p);
}

}  // namespace

TEST_CASE("fans with theta / (g - 1) elements: their top edges match growth x the last layer", "[layers]") {
  // A square obstacle: four right-angle fans. 5 per pi gives 3 elements, top edges of about
  // (pi / 6) x 0.057 = 0.03 against growth x the last layer (0.011).
  const Geometry g = build_geometry({square(5.0, "far"), square(0.5, "wall")});
  LayerSettings s = settings(1e-4, 1.2, 26);
  s.fan_elements_per_pi = fan_elements_matching_core(s.growth);
  CHECK(s.fan_elements_per_pi == Approx(kPi / 0.2));
  CHECK(fan_elements_matching_core(3.0) == 5.0);  // never below 5 per pi
  const LayerMesh m = build_boundary_layers(g, curves_by_name(g, {"wall"}, "test"), s);
  REQUIRE(m.fan_sizes.size() == 4);
  for (const int f : m.fan_sizes) CHECK(f == 8);
  // Every fan's top edges (consecutive fan rays of one wall node).
  int fan_edges = 0;
  for (std::size_t r = 0; r + 1 < m.rays.size(); ++r) {
    const LayerRay& a = m.rays[r];
    const LayerRay& b = m.rays[r + 1];
    if (a.wall_node != b.wall_node) continue;
    const double last = dist(m.nodes[a.nodes.back()], m.nodes[a.nodes[a.nodes.size() - 2]]);
    CHECK(dist(m.nodes[a.nodes.back()], m.nodes[b.nodes.back()]) <= 1.1 * s.growth * last);
    ++fan_edges;
  }
  CHECK(fan_edges == 4 * 8);
  CHECK(measure_layers(m, s.first_height).max_angle_deg <= 110.0);
}

TEST_CASE("dense wall nodes: columns merge so that the front's spacing follows the last layer", "[layers]") {
  // 512 wall nodes on a circle of radius 1 (0.012 apart) under layers whose last is about 0.04 high:
  // without merging the front's edges are a third of the last layer's height.
  const Geometry g = build_geometry({square(5.0, "far"), circle(1.0, 512, "wall")});
  LayerSettings s = settings(1e-3, 1.3, 14);
  s.merge_span = 0.0;
  const LayerMesh plain = build_boundary_layers(g, curves_by_name(g, {"wall"}, "test"), s);
  const std::vector<double> before = front_edges_over_last_layer(plain);
  CHECK(*std::max_element(before.begin(), before.end()) < 0.5);
  s.merge_span = 1.2;
  const LayerMesh m = build_boundary_layers(g, curves_by_name(g, {"wall"}, "test"), s);
  const std::vector<double> after = front_edges_over_last_layer(m);
  CHECK(*std::min_element(after.begin(), after.end()) >= 0.5);
  CHECK(*std::max_element(after.begin(), after.end()) <= 1.2 + 1e-9);
  int merged = 0;
  for (const LayerRay& r : m.rays) merged += r.merged ? 1 : 0;
  CHECK(merged >= 256);
  CHECK(m.fronts.at(0).nodes.size() == m.rays.size() - static_cast<std::size_t>(merged));
  const LayerMeasures q = measure_layers(m, s.first_height);
  CHECK(q.first_height_within_2pct == 1.0);
  CHECK(q.inverted_cells == 0);
  CHECK(q.growth_max <= 1.25 * 1.3 + 1e-9);
  CHECK(q.max_angle_deg <= 95.0);  // the merges' triangles: no angle above ~90 degrees
  CHECK(cell_area(m) == Approx(std::abs(front_area(m)) - std::abs(polygon_area(g.curves[1].points))).epsilon(1e-9));
}

TEST_CASE("diverging rays: the wall is refined so that the front is as dense as its last layer", "[layers]") {
  // A nose of radius 0.1 with 32 wall nodes under layers 0.057 thick: the rays diverge, the
  // front's edges are 3.2 last layers long.
  const Geometry g = build_geometry({square(5.0, "far"), circle(0.1, 32, "wall")});
  LayerSettings s = settings(1e-4, 1.2, 26);
  s.split_span = 0.0;
  s.merge_span = 0.0;
  const LayerMesh plain = build_boundary_layers(g, curves_by_name(g, {"wall"}, "test"), s);
  const std::vector<double> before = front_edges_over_last_layer(plain);
  CHECK(*std::min_element(before.begin(), before.end()) > 3.0);
  s.split_span = 1.6;
  const LayerMesh m = build_boundary_layers(g, curves_by_name(g, {"wall"}, "test"), s);
  const std::vector<double> after = front_edges_over_last_layer(m);
  CHECK(*std::max_element(after.begin(), after.end()) <= 1.6);
  CHECK(m.wall_nodes == 32 * 3);  // each segment in three
  // The new wall nodes lie on the wall's segments: the first cells are exact over them.
  const LayerMeasures q = measure_layers(m, s.first_height);
  CHECK(q.wall_cells == 32 * 3);
  CHECK(q.first_height_within_2pct == 1.0);
  CHECK(q.inverted_cells == 0);
  CHECK(m.repairs == 0);
  CHECK(cell_area(m) == Approx(std::abs(front_area(m)) - std::abs(polygon_area(g.curves[1].points))).epsilon(1e-9));
}

TEST_CASE("a wall segment between two fans: its columns merge in pairs, no half front edge", "[layers]") {
  // A hexagon of side 0.013: a fan at each corner (60 degrees), parallel rays along each side. The
  // last layer of 0.01997 is thin (a third of the one below), so each side is split into parts of at
  // most 1.6 last layers and the columns merge in pairs under the layers below. An odd number of
  // parts would leave one front edge of a single part, half its neighbours, beside a fan, and the
  // core's triangles on such an edge are flat.
  RawCurve hexagon{"wall", {}, "test", 1, {}};
  for (int k = 0; k <= 6; ++k)
    hexagon.points.push_back({0.013 * std::cos(kPi * (k % 6) / 3.0), 0.013 * std::sin(kPi * (k % 6) / 3.0)});
  const Geometry g = build_geometry({square(5.0, "far"), hexagon});
  for (const bool split : {false, true}) {
    LayerSettings s;
    s.first_height = 1e-4;
    s.growth = 1.2;
    s.thickness = 0.01997;
    s.split_quads = split;
    s.max_ray_tilt_deg = split ? 5.0 : 0.0;
    const LayerMesh m = build_boundary_layers(g, curves_by_name(g, {"wall"}, "test"), s);
    REQUIRE(m.fan_sizes.size() == 6);
    int merged = 0;
    for (const LayerRay& r : m.rays) merged += r.merged ? 1 : 0;
    REQUIRE(merged > 0);
    // The front edges between two wall nodes (not inside a fan): all of one length.
    std::vector<int> wall_of(m.nodes.size(), -1);
    for (const LayerRay& r : m.rays) wall_of[r.nodes.back()] = r.wall_node;
    double shortest = 1e9, longest = 0.0;
    const std::vector<int>& front = m.fronts.at(0).nodes;
    for (std::size_t i = 0; i < front.size(); ++i) {
      const int a = front[i], b = front[(i + 1) % front.size()];
      if (wall_of[a] == wall_of[b]) continue;
      shortest = std::min(shortest, dist(m.nodes[a], m.nodes[b]));
      longest = std::max(longest, dist(m.nodes[a], m.nodes[b]));
    }
    CHECK(shortest >= 0.9 * longest);  // a single-part edge would be half the others
    const LayerMeasures q = measure_layers(m, s.first_height);
    CHECK(q.inverted_cells == 0);
    CHECK(q.first_height_within_2pct == 1.0);
    CHECK(m.repairs == 0);
  }
}

TEST_CASE("the wall is refined for the graded thickness where a collision thins the layer", "[layers]") {
  // The nose of the test above with a small obstacle 0.02 off its wall: the ray facing it stops at
  // 0.4 x 0.02, and the grading thins its neighbours too (jumps of at most 1.3). Their front edges
  // are measured at the thickness they end with, not at the thickness they would have alone.
  const Geometry g = build_geometry({square(5.0, "far"), circle(0.1, 32, "wall"), [] {
                                       RawCurve box = square(0.01, "box");
                                       for (Vec2& p : box.points) p.x += 0.13;
                                       return box;
                                     }()});
  LayerSettings s = settings(1e-4, 1.2, 26);
  s.merge_span = 0.0;
  const LayerMesh m = build_boundary_layers(g, curves_by_name(g, {"wall"}, "test"), s);
  const LayerMeasures q = measure_layers(m, s.first_height);
  REQUIRE(q.min_thickness < 0.5 * q.max_thickness);  // the collision thinned the layer
  CHECK(m.repairs == 0);
  // Each front edge over the stack's last whole layer under the lower of its two tops (the last
  // layer itself ends at the ray's thickness: a quarter to 1.25 of the stack's next).
  std::vector<double> top_height(m.nodes.size(), -1.0);
  for (const LayerRay& r : m.rays)
    if (!r.nodes.empty())
      top_height[r.nodes.back()] = r.correction * dist(m.nodes[r.nodes.back()], m.nodes[r.wall_node]);
  double worst = 0.0;
  const std::vector<int>& front = m.fronts.at(0).nodes;
  for (std::size_t i = 0; i < front.size(); ++i) {
    const int a = front[i], b = front[(i + 1) % front.size()];
    const double t = std::min(top_height[a], top_height[b]);
    double stack = 0.0, layer = s.first_height;
    while (stack + layer < t * (1.0 - 1e-9)) {
      stack += layer;
      layer *= s.growth;
    }
    worst = std::max(worst, dist(m.nodes[a], m.nodes[b]) / (layer / s.growth));
  }
  CHECK(worst <= 1.6);  // 5.7 measured at the thickness each ray would have alone
  CHECK(q.first_height_within_2pct == 1.0);
  CHECK(q.inverted_cells == 0);
  CHECK(q.max_thickness_jump <= 1.3 + 1e-9);
}

TEST_CASE("a coarse polygon in triangles: each fan has one front edge, as long as those beside it", "[layers]") {
  // A bolt hole as a 32-gon (radius 0.2, vertices turning by 11.25 degrees) with 8 layers of split
  // quads: the 5 degree ray tilt limit gives every vertex a fan of two elements. The core's spacing
  // at a front node follows the node's front edges, so the fan's front should be about as long as
  // the edges of the wall segments beside it: its middle column ends at the last layer and the fan
  // has one front edge (two half-length edges would make the core fine along every segment). Below, the
  // fan keeps its two elements' angles.
  const Geometry g = build_geometry({square(5.0, "far"), circle(0.2, 32, "wall")});
  for (const bool split : {false, true}) {
    LayerSettings s = settings(0.002, 1.2, 8);
    s.split_quads = split;
    s.max_ray_tilt_deg = split ? 5.0 : 0.0;
    s.fan_elements_per_pi = fan_elements_matching_core(s.growth);
    const LayerMesh m = build_boundary_layers(g, curves_by_name(g, {"wall"}, "test"), s);
    const LayerMeasures q = measure_layers(m, s.first_height);
    CHECK(q.inverted_cells == 0);
    CHECK(q.first_height_within_2pct == 1.0);
    if (!split) {  // quads: no fan below 45 degrees, the rays smoothed across the vertices
      CHECK(m.fan_sizes.empty());
      continue;
    }
    REQUIRE(m.fan_sizes.size() == 32);
    for (const int f : m.fan_sizes) CHECK(f == 2);
    std::vector<int> wall_of(m.nodes.size(), -1);
    for (const LayerRay& r : m.rays) wall_of[r.nodes.back()] = r.wall_node;
    double in_fans = 1e9, between = 0.0;
    int fan_edges = 0;
    const std::vector<int>& front = m.fronts.at(0).nodes;
    for (std::size_t i = 0; i < front.size(); ++i) {
      const int a = front[i], b = front[(i + 1) % front.size()];
      const double length = dist(m.nodes[a], m.nodes[b]);
      if (wall_of[a] == wall_of[b]) {
        in_fans = std::min(in_fans, length);
        ++fan_edges;
      } else {
        between = std::max(between, length);
      }
    }
    CHECK(fan_edges == 32);
    CHECK(in_fans >= 0.6 * between);
    CHECK(q.max_angle_deg <= 96.0);  // 90 + half the ray tilt limit's 10 degrees, or of a fan element
  }
}

TEST_CASE("NACA 0012 with layers: the core's triangles on the front and the junction", "[app][layers]") {
  // cases/naca0012's geometry with the default settings (the best preset) and the layers.
  const std::string dir = pdmesh::test::source_dir() + "/cases/naca0012/";
  const fs::path out = pdmesh_test::fresh_path("layer_junction");
  fs::remove_all(out);
  CaseConfig c = parse_case_text(
      "[geometry]\nfiles = [\"" + dir + "airfoil.crv\", \"" + dir +
          "farfield.crv\"]\ncurve_names = [\"upper\", \"lower\", \"bottom\", \"right\", \"top\", \"left\"]\n"
          "[simulation]\ndevice = \"host\"\n[output]\nformats = [\"msh\"]\n"
          "[[boundary_layer]]\ncurves = [\"upper\", \"lower\"]\nfirst_height = 1e-5\ngrowth = 1.2\n"
          "thickness = 0.05\nelements = \"quads\"\n",
      out / "case.toml");
  c.out_dir = out;
  c.quiet = true;
  REQUIRE(run_mesh(c) == 0);
  const nlohmann::json layer = read_quality_json(out / "quality.json")["boundary_layer"];
  // Every core triangle, those on the front included (26 degrees with 5 fan elements, unmerged
  // columns and the nose's sparse front).
  CHECK(layer["core_min_angle"].get<double>() >= 34.0);
  CHECK(layer["tables"][0]["first_height_within_2pct"].get<double>() == 1.0);
  CHECK(layer["tables"][0]["max_angle"].get<double>() <= 110.0);
  // The junction: the core triangle's height on each front edge over the last layer's.
  CHECK(layer["junction"]["max"].get<double>() <= 1.5);
  fs::remove_all(out);
}

TEST_CASE("UIUC E387 with triangle layers: the core at the nose's fans as good as with quads", "[app][layers]") {
  // The user corpus' E387 (61 points, a sharp nose) with a y+ = 1 layer: split quads keep their
  // rays within 5 degrees of the wall normals, so the nose's corners get fans with straight stretches
  // of parallel rays between them; their columns merge in pairs up to the fans, and the core's
  // first row on the even front is as good as the rest of the core.
  const std::string dat = pdmesh::test::source_dir() + "/cases/user_corpus/e387/e387.dat";
  const fs::path out = pdmesh_test::fresh_path("layer_junction_e387");
  fs::remove_all(out);
  CaseConfig c = parse_case_text("[geometry]\nfiles = [\"" + dat +
                                     "\"]\n[farfield]\nshape = \"circle\"\nsize = 20\n"
                                     "[simulation]\ndevice = \"host\"\n[output]\nformats = [\"msh\"]\n"
                                     "[[boundary_layer]]\ncurves = [\"upper\", \"lower\"]\ny_plus = 1\n"
                                     "reynolds = 6e6\nreference_length = 1\ngrowth = 1.2\nthickness = 0.02\n"
                                     "elements = \"triangles\"\n",
                                 out / "case.toml");
  c.out_dir = out;
  c.quiet = true;
  REQUIRE(run_mesh(c) == 0);
  const nlohmann::json layer = read_quality_json(out / "quality.json")["boundary_layer"];
  CHECK(layer["core_min_angle"].get<double>() >= 42.0);
  CHECK(layer["tables"][0]["inverted_cells"].get<int>() == 0);
  CHECK(layer["tables"][0]["max_angle"].get<double>() <= 96.0);
  fs::remove_all(out);
}

TEST_CASE("a steep junction gets a pinned core node on its ray at growth x the last layer", "[layers]") {
  // A circle's layers; a core with one node straight up a ray at 1.8 last layers (a node of the
  // core's second row joined to the top, as a random fill can leave it) and one at 1.2 up another.
  const Geometry g = build_geometry({square(5.0, "far"), circle(0.5, 192, "wall")});
  LayeredCase layered;
  LayerSection section;
  section.settings = settings(1e-3, 1.2, 20);
  section.mesh = build_boundary_layers(g, curves_by_name(g, {"wall"}, "test"), section.settings);
  layered.sections.push_back(std::move(section));
  const LayerMesh& m = layered.sections[0].mesh;
  const LayerFront& f = m.fronts.at(0);
  REQUIRE(f.closed);
  const std::size_t n = f.nodes.size();
  // Two unmerged rays a quarter turn apart whose front edges are at most 1.2 steps long (no lift).
  std::vector<const LayerRay*> picked;
  std::vector<std::size_t> at_front;
  for (const LayerRay& r : m.rays) {
    if (r.merged || r.nodes.size() < 2) continue;
    const auto k =
        static_cast<std::size_t>(std::find(f.nodes.begin(), f.nodes.end(), r.nodes.back()) - f.nodes.begin());
    REQUIRE(k < n);
    const double step = 1.2 * dist(m.nodes[r.nodes.back()], m.nodes[r.nodes[r.nodes.size() - 2]]);
    const double longest = std::max(dist(m.nodes[f.nodes[(k + n - 1) % n]], m.nodes[f.nodes[k]]),
                                    dist(m.nodes[f.nodes[k]], m.nodes[f.nodes[(k + 1) % n]]));
    if (longest > 1.2 * step) continue;
    if (!at_front.empty() && std::min((k + n - at_front[0]) % n, (at_front[0] + n - k) % n) < n / 4) continue;
    picked.push_back(&r);
    at_front.push_back(k);
    if (picked.size() == 2) break;
  }
  REQUIRE(picked.size() == 2);
  const auto top = [&](const LayerRay& r) { return m.nodes[r.nodes.back()]; };
  const auto below = [&](const LayerRay& r) { return m.nodes[r.nodes[r.nodes.size() - 2]]; };
  Mesh core;
  for (const int v : f.nodes) core.points.push_back(m.nodes[v]);
  const Vec2 far = top(*picked[0]) + (top(*picked[0]) - below(*picked[0])) * 1.8;
  const Vec2 fine = top(*picked[1]) + (top(*picked[1]) - below(*picked[1])) * 1.2;
  const int far_i = static_cast<int>(core.points.size()), fine_i = far_i + 1;
  core.points.push_back(far);
  core.points.push_back(fine);
  const auto fan_over = [&](std::size_t k, int apex) {
    const int a = static_cast<int>((k + n - 1) % n), b = static_cast<int>(k), c = static_cast<int>((k + 1) % n);
    core.triangles.push_back({a, b, apex});
    core.triangles.push_back({b, c, apex});
  };
  fan_over(at_front[0], far_i);
  fan_over(at_front[1], fine_i);

  // The far node's top, and its front neighbours (the far node is within 45 degrees of their rays
  // too); not the top with a node at 1.2 last layers.
  const std::vector<Vec2> steep = steep_junctions(layered, core, 1.45);
  const auto listed = [&](Vec2 p) {
    return std::any_of(steep.begin(), steep.end(), [&](Vec2 q) { return q.x == p.x && q.y == p.y; });
  };
  CHECK(listed(top(*picked[0])));
  CHECK_FALSE(listed(top(*picked[1])));
  for (const Vec2& p : steep)
    CHECK(dist(p, top(*picked[0])) <= 1.2 * 1.2 * dist(top(*picked[0]), below(*picked[0])) + 1e-12);

  NodeSet nodes;
  for (std::size_t i = 0; i < n; ++i) nodes.add(core.points[i], 0.01, NodeKind::Fixed, 0);
  nodes.add(far, 0.01, NodeKind::Interior, -1);
  nodes.add(fine, 0.01, NodeKind::Interior, -1);
  REQUIRE(place_first_row(nodes, layered, &steep) == 1);
  const Vec2 want = top(*picked[0]) + (top(*picked[0]) - below(*picked[0])) * 1.2;
  CHECK(nodes.x[static_cast<std::size_t>(far_i)].x == Approx(want.x).margin(1e-12));
  CHECK(nodes.x[static_cast<std::size_t>(far_i)].y == Approx(want.y).margin(1e-12));
  CHECK(nodes.kind[static_cast<std::size_t>(far_i)] == NodeKind::Fixed);
  CHECK(nodes.x[static_cast<std::size_t>(fine_i)].x == fine.x);
  CHECK(nodes.kind[static_cast<std::size_t>(fine_i)] == NodeKind::Interior);
}
