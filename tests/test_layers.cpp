// The boundary-layer generator (host/layers): exact first height and growth on a circle, fans at
// convex corners, concave corners, shrinking between close curves, the core-spacing stop, the
// quad split, the measures, and bad settings refused by name.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "core/errors.hpp"
#include "core/predicates.hpp"
#include "error_message.hpp"
#include "geometry/geometry.hpp"
#include "layers/boundary_layers.hpp"
#include "layers/front_geometry.hpp"
#include "layers/layer_measures.hpp"

using namespace pdmesh;

namespace {

const double kPi = std::acos(-1.0);

RawCurve circle(Vec2 c, double r, int n, const std::string& name) {
  RawCurve curve{name, {}, "test", 1, {}};
  for (int i = 0; i < n; ++i)
    curve.points.push_back({c.x + r * std::cos(2 * kPi * i / n), c.y + r * std::sin(2 * kPi * i / n)});
  curve.points.push_back(curve.points.front());
  return curve;
}

RawCurve box(Vec2 lo, Vec2 hi, int per_side, const std::string& name) {
  const Vec2 c[4] = {lo, {hi.x, lo.y}, hi, {lo.x, hi.y}};
  RawCurve curve{name, {}, "test", 1, {}};
  for (int s = 0; s < 4; ++s)
    for (int i = 0; i < per_side; ++i) {
      const double t = static_cast<double>(i) / per_side;
      curve.points.push_back(c[s] + t * (c[(s + 1) % 4] - c[s]));
    }
  curve.points.push_back(lo);
  return curve;
}

// The plain generator: no wall refinement and no column merging (their own tests turn them on).
LayerSettings settings(double h1, double g, double thickness, int layers = 0) {
  LayerSettings s;
  s.first_height = h1;
  s.growth = g;
  s.thickness = thickness;
  s.layers = layers;
  s.split_span = 0.0;
  s.merge_span = 0.0;
  return s;
}

// Every pair of cell edges that meet other than at a shared node, each pair whose bounding boxes
// overlap tested exactly (a sweep over the boxes sorted by their left side, independent of the
// generator's grid): 0 for a valid layer.
int crossing_edges(const LayerMesh& m) {
  struct Edge {
    int a, b;
    double x0, x1, y0, y1;  // the bounding box
  };
  std::vector<Edge> edges;
  for (const LayerCell& c : m.cells) {
    const int k = c.triangle() ? 3 : 4;
    for (int i = 0; i < k; ++i) {
      const Vec2 p = m.nodes[c.v[i]], q = m.nodes[c.v[(i + 1) % k]];
      edges.push_back(
          {c.v[i], c.v[(i + 1) % k], std::min(p.x, q.x), std::max(p.x, q.x), std::min(p.y, q.y), std::max(p.y, q.y)});
    }
  }
  std::sort(edges.begin(), edges.end(), [](const Edge& e, const Edge& f) { return e.x0 < f.x0; });
  int bad = 0;
  for (std::size_t i = 0; i < edges.size(); ++i)
    // Boxes that overlap in x: those after i whose left side is not right of i's right side.
    for (std::size_t j = i + 1; j < edges.size() && edges[j].x0 <= edges[i].x1; ++j) {
      const Edge& a = edges[i];
      const Edge& b = edges[j];
      if (a.a == b.a || a.a == b.b || a.b == b.a || a.b == b.b) continue;
      if (a.y1 < b.y0 || b.y1 < a.y0) continue;  // the boxes are apart
      if (segments_intersect(m.nodes[a.a], m.nodes[a.b], m.nodes[b.a], m.nodes[b.b])) ++bad;
    }
  return bad;
}

int cells_of(const LayerMesh& m, LayerCellKind kind) {
  int n = 0;
  for (const LayerCell& c : m.cells) n += c.kind == kind ? 1 : 0;
  return n;
}

}  // namespace

TEST_CASE("the crossing check counts edges that cross, not edges that share a node", "[layers]") {
  // Two quads side by side share an edge; a third, tilted over the second's far side, crosses it.
  LayerMesh m;
  m.nodes = {{0, 0}, {1, 0}, {1, 1}, {0, 1}, {2, 0}, {2, 1}, {1.5, 0.5}, {2.5, 0.4}, {2.5, 0.6}, {1.5, 0.6}};
  LayerCell left, right, over;
  left.v = {0, 1, 2, 3};
  right.v = {1, 4, 5, 2};
  CHECK(crossing_edges(m) == 0);
  m.cells = {left, right};
  CHECK(crossing_edges(m) == 0);
  over.v = {6, 7, 8, 9};
  m.cells.push_back(over);
  // Its bottom and top edges cross the right quad's side x = 2.
  CHECK(crossing_edges(m) == 2);
}

TEST_CASE("circle: the first height and the growth are exact, no fan", "[layers]") {
  const Geometry g = build_geometry({box({-5, -5}, {5, 5}, 4, "far"), circle({0, 0}, 1.0, 128, "wall")});
  const LayerSettings s = settings(1e-3, 1.2, 0.0, 10);
  const LayerMesh m = build_boundary_layers(g, curves_by_name(g, {"wall"}, "test"), s);
  const LayerMeasures q = measure_layers(m, s.first_height);
  CHECK(m.fan_sizes.empty());
  CHECK(m.repairs == 0);
  CHECK(m.wall_nodes == 128);
  CHECK(q.quads == 128 * 10);
  CHECK(q.triangles == 0);
  CHECK(q.wall_cells == 128);
  CHECK(q.first_height_within_2pct == 1.0);
  CHECK(q.first_height_max_error < 1e-9);
  CHECK(q.growth_median == Approx(1.2).epsilon(1e-9));
  CHECK(q.growth_max == Approx(1.2).epsilon(1e-9));
  CHECK(q.max_layers == 10);
  CHECK(q.min_thickness == Approx(1e-3 * (std::pow(1.2, 10) - 1) / 0.2).epsilon(1e-12));
  CHECK(q.max_thickness_jump == Approx(1.0).epsilon(1e-12));
  CHECK(q.inverted_cells == 0);
  // The layers grow outwards (into the domain): every layer node is farther from the centre than 1.
  for (std::size_t i = m.wall_nodes; i < m.nodes.size(); ++i) REQUIRE(norm(m.nodes[i]) > 1.0);
  // One closed front of 128 nodes at the top of each ray.
  REQUIRE(m.fronts.size() == 1);
  CHECK(m.fronts[0].closed);
  CHECK(m.fronts[0].nodes.size() == 128);
  CHECK(crossing_edges(m) == 0);
}

TEST_CASE("square obstacle: fans of >= 5 elements per pi at its convex corners", "[layers]") {
  const Geometry g = build_geometry({box({-5, -5}, {5, 5}, 4, "far"), box({0, 0}, {1, 1}, 10, "wall")});
  const LayerSettings s = settings(1e-3, 1.2, 0.05);
  const LayerMesh m = build_boundary_layers(g, curves_by_name(g, {"wall"}, "test"), s);
  const LayerMeasures q = measure_layers(m, s.first_height);
  // A right-angle corner turns by pi/2: ceil(5 x 1/2) = 3 elements.
  CHECK(m.fan_sizes == std::vector<int>{3, 3, 3, 3});
  CHECK(cells_of(m, LayerCellKind::Fan) == 4 * 3 * q.max_layers);
  CHECK(q.first_height_within_2pct == 1.0);
  CHECK(q.inverted_cells == 0);
  CHECK(q.max_angle_deg < 150.0);
  CHECK(q.max_thickness_jump <= 1.3 + 1e-12);
  CHECK(crossing_edges(m) == 0);
}

TEST_CASE("a fan has enough elements for its front edges to be no longer than the core's spacing", "[layers]") {
  const Geometry g = build_geometry({box({-5, -5}, {5, 5}, 4, "far"), box({0, 0}, {1, 1}, 10, "wall")});
  const LayerSettings s = settings(1e-3, 1.2, 0.05);
  // At the corners' tops (0.05 out) the core asks for 0.01: a right angle's arc of 0.05 x pi/2 =
  // 0.0785 needs ceil(7.85) = 8 elements (5 per pi alone would give 3).
  const CoreSpacing core = [](Vec2) { return 0.01; };
  const LayerMesh m = build_boundary_layers(g, curves_by_name(g, {"wall"}, "test"), s, core);
  CHECK(m.fan_sizes == std::vector<int>{8, 8, 8, 8});
  int fan_edges = 0;
  for (std::size_t r = 0; r + 1 < m.rays.size(); ++r) {
    const LayerRay& a = m.rays[r];
    const LayerRay& b = m.rays[r + 1];
    if (!a.fan || a.wall_node != b.wall_node) continue;
    ++fan_edges;
    CHECK(dist(m.nodes[a.nodes.back()], m.nodes[b.nodes.back()]) <= 0.01 + 1e-12);
  }
  CHECK(fan_edges == 4 * 8);
  const LayerMeasures q = measure_layers(m, s.first_height, core);
  CHECK(q.inverted_cells == 0);
  CHECK(crossing_edges(m) == 0);
  // A coarse core spacing leaves the 5-per-pi count.
  const LayerMesh coarse = build_boundary_layers(g, curves_by_name(g, {"wall"}, "test"), s, [](Vec2) { return 1.0; });
  CHECK(coarse.fan_sizes == std::vector<int>{3, 3, 3, 3});
}

TEST_CASE("square box with a square hole: concave corners without crossing, fans on the hole", "[layers]") {
  const Geometry g = build_geometry({box({0, 0}, {1, 1}, 12, "box"), box({0.4, 0.4}, {0.6, 0.6}, 4, "hole")});
  const LayerSettings s = settings(1e-3, 1.2, 0.08);
  const LayerMesh m = build_boundary_layers(g, curves_by_name(g, {"box", "hole"}, "test"), s);
  const LayerMeasures q = measure_layers(m, s.first_height);
  CHECK(m.fan_sizes.size() == 4);  // the hole's corners only: the box's are concave
  CHECK(q.inverted_cells == 0);
  CHECK(crossing_edges(m) == 0);
  CHECK(q.max_thickness_jump <= 1.3 + 1e-12);
  CHECK(q.first_height_within_2pct == 1.0);
  // The box's layers grow inwards, and keep some layers at its corners.
  for (const LayerRay& r : m.rays) {
    const Vec2 p = m.nodes[r.wall_node];
    if (m.nodes[r.nodes.back()].x < 0.0 || m.nodes[r.nodes.back()].x > 1.0) FAIL("a layer node outside the box");
    if ((p.x == 0.0 || p.x == 1.0) && (p.y == 0.0 || p.y == 1.0)) CHECK(r.nodes.size() > 3);
  }
}

TEST_CASE("a blunt edge with thick layers: the column between its two fans ends", "[layers]") {
  // A plate with blunt ends 0.0012 high (clarky's trailing edge) and layers of 0.1: each end is one
  // wall segment between two right-angled convex corners with fans of the pipeline's size
  // (theta / (g - 1) elements). The fans' edge rays over the end run parallel, 0.0012 apart, up
  // to the top, where the core met that short front edge between the fans' edges of about 0.02
  // with flat triangles. The column ends where its neighbours come within merge_span of a layer,
  // like any other column, and no front edge is that short any more.
  RawCurve plate{"plate", {}, "test", 1, {}};
  const double h = 0.0012;
  for (int i = 0; i <= 20; ++i) plate.points.push_back({0.05 * i, 0.0});
  for (int i = 20; i >= 0; --i) plate.points.push_back({0.05 * i, h});
  plate.points.push_back(plate.points.front());
  const Geometry g = build_geometry({box({-3, -3}, {4, 3}, 4, "far"), plate});
  LayerSettings s;
  s.first_height = 1e-4;
  s.growth = 1.2;
  s.thickness = 0.1;
  s.fan_elements_per_pi = std::numbers::pi / (s.growth - 1.0);
  const LayerMesh m = build_boundary_layers(g, curves_by_name(g, {"plate"}, "test"), s);
  const LayerMeasures q = measure_layers(m, s.first_height);
  CHECK(q.inverted_cells == 0);
  CHECK(crossing_edges(m) == 0);
  CHECK(q.first_height_within_2pct == 1.0);
  int merged_fan_rays = 0;
  for (const LayerRay& r : m.rays) merged_fan_rays += r.fan && r.merged ? 1 : 0;
  CHECK(merged_fan_rays == 2);  // one at each end
  REQUIRE(m.fronts.size() == 1);
  const std::vector<int>& f = m.fronts[0].nodes;
  double shortest = 1.0;
  for (std::size_t i = 0; i < f.size(); ++i)
    shortest = std::min(shortest, dist(m.nodes[f[i]], m.nodes[f[(i + 1) % f.size()]]));
  CHECK(shortest > 4.0 * h);
}

TEST_CASE("two close circles: the layers shrink in the gap, no crossing, jumps <= 1.3", "[layers]") {
  // 384 wall nodes (0.016 apart): the core's strip between the fronts (0.2 x the gap, 0.02) is wider
  // than the front's edges, and the facing rays stop at gap_fraction of the gap.
  const double gap = 0.1;
  const Geometry g = build_geometry({box({-6, -5}, {6, 5}, 4, "far"), circle({-1.0 - gap / 2, 0}, 1.0, 384, "left"),
                                     circle({1.0 + gap / 2, 0}, 1.0, 384, "right")});
  const LayerSettings s = settings(1e-3, 1.2, 0.3);
  const LayerMesh m = build_boundary_layers(g, curves_by_name(g, {"left", "right"}, "test"), s);
  const LayerMeasures q = measure_layers(m, s.first_height);
  CHECK(q.inverted_cells == 0);
  CHECK(crossing_edges(m) == 0);
  CHECK(q.max_thickness_jump <= 1.3 + 1e-12);
  CHECK(q.max_thickness == Approx(0.3).epsilon(1e-9));  // away from the gap
  CHECK(q.first_height_within_2pct == 1.0);
  // The rays that face the gap stop at gap_fraction of it, leaving room to the core, found by the
  // collision limits rather than by the final checks' shrinking.
  CHECK(m.repairs == 0);
  int facing = 0;
  for (const LayerRay& r : m.rays) {
    const Vec2 p = m.nodes[r.wall_node];
    if (std::abs(p.y) < 1e-12 && std::abs(p.x) < 0.1) {
      CHECK(r.thickness <= s.gap_fraction * gap * (1.0 + 1e-12));
      CHECK(r.thickness >= 0.95 * s.gap_fraction * gap);  // smoothed with its neighbours only
      ++facing;
    }
  }
  CHECK(facing == 2);
  REQUIRE(m.fronts.size() == 2);
  // With 96 wall nodes (0.065 apart) that strip would be a third of the front's edges: the facing
  // rays stop lower, leaving the core at least the front edge beside their tops.
  const Geometry coarse = build_geometry({box({-6, -5}, {6, 5}, 4, "far"), circle({-1.0 - gap / 2, 0}, 1.0, 96, "left"),
                                          circle({1.0 + gap / 2, 0}, 1.0, 96, "right")});
  const LayerMesh c = build_boundary_layers(coarse, curves_by_name(coarse, {"left", "right"}, "test"), s);
  CHECK(measure_layers(c, s.first_height).inverted_cells == 0);
  CHECK(crossing_edges(c) == 0);
  facing = 0;
  for (std::size_t r = 0; r < c.rays.size(); ++r) {
    const LayerRay& ray = c.rays[r];
    const Vec2 p = c.nodes[ray.wall_node];
    if (std::abs(p.y) < 1e-12 && std::abs(p.x) < 0.1) {
      // Its neighbours in its closed chain.
      const auto chain = std::upper_bound(c.chain_ray_begin.begin(), c.chain_ray_begin.end(), static_cast<int>(r));
      const int b = *(chain - 1), n = *chain - b, k = static_cast<int>(r) - b;
      double edge = 0.0;
      for (const int j : {(k + 1) % n, (k + n - 1) % n})
        edge = std::max(edge, dist(c.nodes[ray.nodes.back()], c.nodes[c.rays[b + j].nodes.back()]));
      CHECK(ray.thickness > s.first_height);
      CHECK(gap - 2.0 * ray.thickness >= edge * (1.0 - 1e-9));
      ++facing;
    }
  }
  CHECK(facing == 2);
}

TEST_CASE("two plates between one and two thicknesses apart: both layers stop at gap_fraction of the gap", "[layers]") {
  // Neither free layer reaches the other plate and the facing rays are parallel (they never cross),
  // but together the layers would fill the gap: each ray must see the plate it faces (within
  // thickness / gap_fraction) and stop at gap_fraction of the distance, the fronts leaving
  // (1 - 2 gap_fraction) of the gap to the core, found by the collision limits (no repair round).
  // The plates' wall nodes are 0.05 apart, below the core's strip of 0.09 (with nodes as far apart
  // as the strip is wide the layers would end earlier: the narrow wedge below).
  const double gap = 0.45, thickness = 0.3;
  const Geometry g =
      build_geometry({box({-6, -5}, {6, 5}, 4, "far"), box({-2, -gap / 2 - 0.5}, {2, -gap / 2}, 80, "low"),
                      box({-2, gap / 2}, {2, gap / 2 + 0.5}, 80, "high")});
  const LayerSettings s = settings(1e-3, 1.2, thickness);
  const LayerMesh m = build_boundary_layers(g, curves_by_name(g, {"low", "high"}, "test"), s);
  const LayerMeasures q = measure_layers(m, s.first_height);
  CHECK(m.repairs == 0);
  CHECK(q.inverted_cells == 0);
  CHECK(crossing_edges(m) == 0);
  CHECK(q.max_thickness_jump <= 1.3 + 1e-12);
  CHECK(q.max_thickness == Approx(thickness).epsilon(1e-9));  // away from the gap
  int facing = 0;
  for (const LayerRay& r : m.rays) {
    const Vec2 p = m.nodes[r.wall_node];
    if (std::abs(std::abs(p.y) - gap / 2) < 1e-12 && std::abs(p.x) <= 1.0) {
      CHECK(r.thickness == Approx(s.gap_fraction * gap).epsilon(1e-9));
      ++facing;
    }
  }
  CHECK(facing == 2 * 41);
}

TEST_CASE("the core spacing stops the layers where the growth into the core is at most the growth", "[layers]") {
  const Geometry g = build_geometry({box({-5, -5}, {5, 5}, 4, "far"), circle({0, 0}, 1.0, 64, "wall")});
  const LayerSettings s = settings(1e-3, 1.2, 1.0);
  const CoreSpacing core = [](Vec2) { return 0.01; };
  const LayerMesh m = build_boundary_layers(g, {1}, s, core);
  const LayerMeasures q = measure_layers(m, s.first_height, core);
  // 1e-3 x 1.2^12 = 0.00892 is the first layer height whose growth to 0.01 is <= 1.2: 13 layers.
  CHECK(q.max_layers == 13);
  CHECK(q.junction_max == Approx(0.01 / (1e-3 * std::pow(1.2, 12))).epsilon(1e-9));
  CHECK(q.growth_with_junction_max <= 1.2 + 1e-9);
}

TEST_CASE("split quads: two triangles each, no angle above 95 degrees on a circle", "[layers]") {
  const Geometry g = build_geometry({box({-5, -5}, {5, 5}, 4, "far"), circle({0, 0}, 1.0, 128, "wall")});
  LayerSettings s = settings(1e-3, 1.2, 0.0, 8);
  s.split_quads = true;
  const LayerMesh m = build_boundary_layers(g, {1}, s);
  const LayerMeasures q = measure_layers(m, s.first_height);
  CHECK(q.quads == 0);
  CHECK(q.triangles == 2 * 128 * 8);
  CHECK(q.max_angle_deg < 95.0);
  CHECK(q.first_height_within_2pct == 1.0);
  CHECK(q.inverted_cells == 0);
}

TEST_CASE("the measures see a wrong first height and an inverted cell", "[layers]") {
  const Geometry g = build_geometry({box({-5, -5}, {5, 5}, 4, "far"), circle({0, 0}, 1.0, 32, "wall")});
  const LayerSettings s = settings(1e-3, 1.2, 0.0, 5);
  LayerMesh m = build_boundary_layers(g, {1}, s);
  const int moved = m.rays[3].nodes[1];
  m.nodes[moved] = m.nodes[moved] + 0.05e-3 * m.rays[3].direction;  // 5 % higher
  LayerMeasures q = measure_layers(m, s.first_height);
  CHECK(q.first_height_within_2pct == Approx(30.0 / 32.0));
  CHECK(q.first_height_max_error == Approx(0.05).epsilon(0.02));
  CHECK(q.inverted_cells == 0);
  const int top = m.rays[7].nodes.back();
  m.nodes[top] = m.nodes[m.rays[7].wall_node] - 1e-3 * m.rays[7].direction;  // inside the wall
  q = measure_layers(m, s.first_height);
  CHECK(q.inverted_cells >= 1);
}

TEST_CASE("bad layer settings are input errors naming the value", "[layers]") {
  const Geometry g = build_geometry({box({-5, -5}, {5, 5}, 4, "far"), circle({0, 0}, 1.0, 32, "wall")});
  using pdmesh_test::error_message;
  auto msg = [&](const LayerSettings& s, std::vector<int> walls = {1}) {
    return error_message<InputError>([&] { build_boundary_layers(g, walls, s); });
  };
  CHECK_THAT(msg(settings(1e-3, 1.0, 0.05)), Catch::Contains("growth = 1 must be greater than 1"));
  CHECK_THAT(msg(settings(1e-3, 0.9, 0.05)), Catch::Contains("growth = 0.9"));
  CHECK_THAT(msg(settings(0.1, 1.2, 0.05)), Catch::Contains("first_height = 0.1 is above the thickness = 0.05"));
  CHECK_THAT(msg(settings(0.0, 1.2, 0.05)), Catch::Contains("first_height = 0 must be a positive number"));
  CHECK_THAT(msg(settings(std::nan(""), 1.2, 0.05)), Catch::Contains("first_height = nan"));
  CHECK_THAT(msg(settings(1e-3, 1.2, 0.0)), Catch::Contains("give either thickness or layers, not neither"));
  CHECK_THAT(msg(settings(1e-3, 1.2, 0.05, 4)), Catch::Contains("not both"));
  CHECK_THAT(msg(settings(1e-3, 1.2, 0.05), {}), Catch::Contains("the list of wall curves is empty"));
  CHECK_THAT(msg(settings(1e-3, 1.2, 0.05), {7}), Catch::Contains("wall curve index 7"));
  CHECK_THAT(error_message<InputError>([&] {
               curves_by_name(g, {"wall", "flap"}, "boundary_layer.curves");
             }),
             Catch::Contains("boundary_layer.curves: unknown curve 'flap' (the geometry's curves: far, wall)"));
  CHECK_THAT(msg(settings(1e-12, 1.000001, 1.0)), Catch::Contains("(at most 10000)"));
  LayerSettings room = settings(1e-3, 1.2, 0.05);
  room.core_room = -1.0;
  CHECK_THAT(msg(room), Catch::Contains("core_room = -1 must be in [0, 10]"));
  CHECK(msg(settings(1e-3, 1.2, 0.05)).empty());  // good settings pass
}

TEST_CASE("open wall chain: the end rays run along the curves that continue the boundary", "[layers]") {
  // A channel [0,4] x [0,1]: the bottom is the wall, the inlet and outlet are upright, the top is
  // slanted so that the outlet meets the bottom at a right angle and the inlet at 90 degrees too.
  std::vector<RawCurve> raw;
  auto add = [&](std::vector<Vec2> pts, const std::string& name) { raw.push_back({name, pts, "test", 1, {}}); };
  std::vector<Vec2> bottom;
  for (int i = 0; i <= 40; ++i) bottom.push_back({0.1 * i, 0.0});
  add(bottom, "bottom");
  add({{4, 0}, {4, 0.5}, {4, 1}}, "outlet");
  add({{4, 1}, {0, 1}}, "top");
  add({{0, 1}, {0, 0.5}, {0, 0}}, "inlet");
  const Geometry g = build_geometry(raw);
  const LayerSettings s = settings(1e-3, 1.2, 0.1);
  const LayerMesh m = build_boundary_layers(g, curves_by_name(g, {"bottom"}, "test"), s);
  const LayerMeasures q = measure_layers(m, s.first_height);
  CHECK(m.repairs == 0);
  CHECK(q.inverted_cells == 0);
  CHECK(crossing_edges(m) == 0);
  CHECK(q.max_thickness == Approx(0.1).epsilon(1e-9));
  CHECK(q.min_thickness == Approx(0.1).epsilon(1e-9));  // the ends keep the full layer
  REQUIRE(m.rays.size() == 41);
  CHECK(m.rays.front().slide_segment >= 0);
  CHECK(m.rays.back().slide_segment >= 0);
  for (const int node : m.rays.front().nodes) CHECK(m.nodes[node].x == 0.0);  // on the inlet
  for (const int node : m.rays.back().nodes) CHECK(m.nodes[node].x == 4.0);   // on the outlet
  // The open front runs up the first ray, along the tops and down the last ray.
  REQUIRE(m.fronts.size() == 1);
  CHECK_FALSE(m.fronts[0].closed);
  CHECK(m.fronts[0].nodes.front() == m.rays.front().wall_node);
  CHECK(m.fronts[0].nodes.back() == m.rays.back().wall_node);
  // The core's boundary: the inlet and outlet start at the end rays' tops (the layer's sides cover
  // them below), the front runs from the first ray's top along the tops to the last ray's top, and
  // together with the top they close one loop.
  const std::vector<RawCurve> core = front_curves(g, curves_by_name(g, {"bottom"}, "test"), m);
  const auto curve = [&](const std::string& name) {
    for (const RawCurve& c : core)
      if (c.name == name) return c;
    FAIL("no curve " << name);
    return RawCurve{};
  };
  const Vec2 first_top = m.nodes[m.rays.front().nodes.back()], last_top = m.nodes[m.rays.back().nodes.back()];
  CHECK(first_top.y == Approx(0.1));
  CHECK(curve("inlet").points.back() == first_top);
  CHECK(curve("inlet").points.front() == Vec2{0, 1});
  CHECK(curve("outlet").points.front() == last_top);
  const RawCurve front = curve("bottom_front");
  CHECK(front.fixed_points);
  CHECK(front.points.front() == first_top);
  CHECK(front.points.back() == last_top);
  for (const Vec2 p : front.points) CHECK(p.y == Approx(0.1));
  const Geometry core_geometry = build_geometry(core);
  CHECK(core_geometry.curves.size() == 4);
}

TEST_CASE("jagged star-shaped walls: valid layers whatever the collisions", "[layers]") {
  // Star polygons with random radii in [1, 2] (a fixed generator: the same shapes everywhere), as
  // holes in a box; thick layers collide with the star's own teeth.
  std::uint64_t state = 12345;
  auto next = [&state] {  // splitmix64
    std::uint64_t z = (state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return static_cast<double>((z ^ (z >> 31)) >> 11) / 9007199254740992.0;
  };
  for (int shape = 0; shape < 6; ++shape) {
    const int n = 12 + 8 * shape;
    RawCurve star{"star", {}, "test", 1, {}};
    for (int i = 0; i < n; ++i) {
      const double a = 2 * kPi * i / n, r = 1.0 + next();
      star.points.push_back({r * std::cos(a), r * std::sin(a)});
    }
    star.points.push_back(star.points.front());
    const Geometry g = build_geometry({box({-4, -4}, {4, 4}, 4, "far"), star});
    const LayerSettings s = settings(1e-3, 1.2, 0.4);
    const LayerMesh m = build_boundary_layers(g, {1}, s);
    const LayerMeasures q = measure_layers(m, s.first_height);
    INFO("shape " << shape << ", " << n << " vertices, " << m.repairs << " repair rounds");
    CHECK(q.inverted_cells == 0);
    CHECK(crossing_edges(m) == 0);
    // Between rays with layers (a notch narrower than its wall's spacing has none at its tip).
    for (std::size_t r = 0; r < m.rays.size(); ++r) {
      const LayerRay& a = m.rays[r];
      const LayerRay& b = m.rays[(r + 1) % m.rays.size()];
      if (a.thickness > 0.0 && b.thickness > 0.0)
        CHECK(std::max(a.thickness, b.thickness) <= (1.3 + 1e-12) * std::min(a.thickness, b.thickness));
    }
    CHECK(q.first_height_within_2pct == 1.0);
    CHECK(q.max_thickness > 0.1);
  }
}

TEST_CASE("max_ray_tilt: split wall cells of a 12-gon stay right-angled outside the fans", "[layers]") {
  // Each vertex turns by 30 degrees, below the fan angle: the bisector rays are 15 degrees off
  // both segments' normals and the split thin cells have 105 degrees. With max_ray_tilt 5 every
  // vertex gets a fan and the cells between them are rectangles.
  const Geometry g = build_geometry({box({-5, -5}, {5, 5}, 4, "far"), circle({0, 0}, 1.0, 12, "wall")});
  LayerSettings s = settings(1e-3, 1.2, 0.0, 8);
  s.split_quads = true;
  auto max_outside_fans = [](const LayerMesh& m) {
    double lo = 1.0;
    for (const LayerCell& c : m.cells) {
      if (c.kind == LayerCellKind::Fan) continue;
      for (int i = 0; i < 3; ++i) {
        const Vec2 u = m.nodes[c.v[(i + 1) % 3]] - m.nodes[c.v[i]], w = m.nodes[c.v[(i + 2) % 3]] - m.nodes[c.v[i]];
        lo = std::min(lo, dot(u, w) / (norm(u) * norm(w)));
      }
    }
    return std::acos(lo) * 180.0 / std::numbers::pi;
  };
  const LayerMesh plain = build_boundary_layers(g, {1}, s);
  CHECK(plain.fan_sizes.empty());
  CHECK(max_outside_fans(plain) > 104.0);
  s.max_ray_tilt_deg = 5.0;
  const LayerMesh m = build_boundary_layers(g, {1}, s);
  CHECK(m.fan_sizes.size() == 12);
  CHECK(max_outside_fans(m) < 90.5);
  const LayerMeasures q = measure_layers(m, s.first_height);
  CHECK(q.first_height_within_2pct == 1.0);
  CHECK(q.inverted_cells == 0);
  CHECK(q.quads == 0);
  // Out of range: an input error naming the value.
  s.max_ray_tilt_deg = 45.0;
  CHECK_THAT(pdmesh_test::error_message<InputError>([&] { build_boundary_layers(g, {1}, s); }),
             Catch::Contains("max_ray_tilt = 45 must be in [0, 45) degrees"));
}

TEST_CASE("tied open chain ends get the same layers where the core spacing differs at them", "[layers][periodic]") {
  // A channel [0,2] x [0,1] with the bottom as the wall; the core's spacing is fine near the outlet,
  // so that the layer stops lower there than at the inlet. Tied, both end columns get the lower one.
  std::vector<RawCurve> raw;
  auto add = [&](std::vector<Vec2> pts, const std::string& name) { raw.push_back({name, pts, "test", 1, {}}); };
  std::vector<Vec2> bottom;
  for (int i = 0; i <= 40; ++i) bottom.push_back({0.05 * i, 0.0});
  add(bottom, "bottom");
  add({{2, 0}, {2, 1}}, "outlet");
  add({{2, 1}, {0, 1}}, "top");
  add({{0, 1}, {0, 0}}, "inlet");
  const Geometry g = build_geometry(raw);
  const LayerSettings s = settings(1e-3, 1.2, 0.1);
  const CoreSpacing core = [](Vec2 p) { return p.x > 1.5 ? 0.01 : 1.0; };
  const std::vector<int> walls = curves_by_name(g, {"bottom"}, "test");
  const LayerMesh free = build_boundary_layers(g, walls, s, core);
  const LayerMesh tied = build_boundary_layers(g, walls, s, core, {{{0.0, 0.0}, {2.0, 0.0}}});
  const auto column = [](const LayerMesh& m, Vec2 wall) {
    const int r = end_ray_at(m, wall);
    REQUIRE(r >= 0);
    std::vector<double> heights;
    for (const int node : m.rays[static_cast<std::size_t>(r)].nodes) heights.push_back(m.nodes[node].y);
    return heights;
  };
  // Untied, the inlet's column is higher (the case the tie is for).
  CHECK(column(free, {0, 0}).size() > column(free, {2, 0}).size());
  CHECK(column(tied, {0, 0}) == column(tied, {2, 0}));
  CHECK(column(tied, {2, 0}) == column(free, {2, 0}));
  CHECK(measure_layers(tied, s.first_height).inverted_cells == 0);
  CHECK(crossing_edges(tied) == 0);
  CHECK(end_ray_at(tied, {1.0, 0.0}) == -1);  // not a chain's end
  CHECK_THROWS_WITH(build_boundary_layers(g, walls, s, core, {{{0.0, 0.0}, {1.0, 0.0}}}),
                    Catch::Contains("no open wall chain ends at (1, 0)"));
}

namespace {

// The distance from p to the segment a -> b.
double segment_distance(Vec2 p, Vec2 a, Vec2 b) {
  const Vec2 d = b - a;
  const double t = std::clamp(dot(p - a, d) / dot(d, d), 0.0, 1.0);
  return norm(p - (a + t * d));
}

}  // namespace

TEST_CASE("a narrow wedge with layers on both walls: the fronts leave the core room for their edges", "[layers]") {
  // A 12-degree wedge, its two walls meeting at the tip, closed by a mouth without layers. The
  // walls' layers collide along the whole wedge and each stops at a share of the gap; towards the
  // tip the gap falls below the front's edges (the wall's spacing), and a core strip narrower than
  // the edges it lies between holds only slivers. Every front node on the lower wall's layer must
  // lie at least about its front edges away from the upper wall's front (the layer ends first), in
  // triangles and in quads.
  const double angle = 12.0 * kPi / 180.0;
  const int n = 60;
  RawCurve lower{"lower", {}, "test", 1, {}}, upper{"upper", {}, "test", 1, {}};
  for (int i = 0; i <= n; ++i) lower.points.push_back({static_cast<double>(i) / n, 0.0});
  for (int i = n; i >= 0; --i) upper.points.push_back({std::cos(angle) * i / n, std::sin(angle) * i / n});
  const RawCurve mouth{"mouth", {{1.0, 0.0}, {std::cos(angle), std::sin(angle)}}, "test", 1, {}};
  const Geometry g = build_geometry({lower, mouth, upper});
  for (const bool quads : {false, true}) {
    LayerSettings s;  // the library's defaults (wall refinement and column merging on)
    s.first_height = 1e-3;
    s.growth = 1.2;
    s.thickness = 0.04;
    s.split_quads = !quads;  // as the pipeline sets triangles
    s.max_ray_tilt_deg = quads ? 0.0 : 5.0;
    INFO((quads ? "quads" : "triangles"));
    const LayerMesh m = build_boundary_layers(g, curves_by_name(g, {"lower", "upper"}, "test"), s);
    const LayerMeasures q = measure_layers(m, s.first_height);
    CHECK(q.inverted_cells == 0);
    CHECK(crossing_edges(m) == 0);
    CHECK(q.first_height_within_2pct == 1.0);
    CHECK(q.max_thickness == Approx(0.04).epsilon(1e-9));  // at the mouth
    REQUIRE(m.fronts.size() == 1);
    const std::vector<int>& front = m.fronts[0].nodes;
    std::vector<int> owner(m.nodes.size(), -1);
    for (std::size_t r = 0; r < m.rays.size(); ++r)
      for (const int v : m.rays[r].nodes) owner[v] = static_cast<int>(r);
    const int lower_curve = curves_by_name(g, {"lower"}, "test")[0];
    auto on = [&](int node, bool lower_wall) {
      const int r = owner[node];
      return r >= 0 && node >= m.wall_nodes && (m.rays[r].curve == lower_curve) == lower_wall &&
             m.nodes[m.rays[r].wall_node] != Vec2{0.0, 0.0};
    };
    int checked = 0;
    double worst = 1e300;
    for (std::size_t i = 1; i + 1 < front.size(); ++i) {
      if (!on(front[i], true)) continue;
      const Vec2 p = m.nodes[front[i]];
      const double edge = std::max(dist(p, m.nodes[front[i - 1]]), dist(p, m.nodes[front[i + 1]]));
      double room = 1e300;
      for (std::size_t j = 0; j + 1 < front.size(); ++j)
        if (on(front[j], false) || on(front[j + 1], false))
          room = std::min(room, segment_distance(p, m.nodes[front[j]], m.nodes[front[j + 1]]));
      worst = std::min(worst, room / edge);
      ++checked;
    }
    INFO("front nodes on the lower wall's layer: " << checked << ", smallest room over front edge " << worst);
    CHECK(checked > 20);
    CHECK(worst >= 0.8);
  }
}
