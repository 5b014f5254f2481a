// The boundary-layer generator on the NACA 0012 and 30P30N geometries of cases/ (the issue's
// settings, no core spacing): first heights, the trailing-edge fan, angles, thickness jumps and
// validity of every cell.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "geometry/geometry_files.hpp"
#include "layers/boundary_layers.hpp"
#include "layers/front_geometry.hpp"
#include "layers/layer_measures.hpp"
#include "source_dir.hpp"

using namespace pdmesh;

namespace {

Geometry case_geometry(const std::string& name, const std::vector<std::string>& curve_names) {
  const std::string dir = pdmesh::test::source_dir() + "/cases/" + name + "/";
  return read_geometry({dir + "airfoil.crv", dir + "farfield.crv"}, curve_names);
}

}  // namespace

TEST_CASE("NACA 0012: h1 1e-5, growth 1.2, thickness 0.05", "[layers]") {
  const Geometry g = case_geometry("naca0012", {"upper", "lower", "bottom", "right", "top", "left"});
  LayerSettings s;
  s.first_height = 1e-5;
  s.growth = 1.2;
  s.thickness = 0.05;
  const LayerMesh m = build_boundary_layers(g, curves_by_name(g, {"upper", "lower"}, "test"), s);
  const LayerMeasures q = measure_layers(m, s.first_height);
  CHECK(q.first_height_within_2pct == 1.0);
  CHECK(q.growth_p95 <= 1.2 + 1e-12);
  CHECK(q.growth_max <= 1.25 * 1.2 + 1e-12);  // a last layer may take up to a quarter more
  CHECK(q.max_angle_deg <= 110.0);
  CHECK(q.angles_above_150 == 0);
  CHECK(q.inverted_cells == 0);
  REQUIRE(m.fan_sizes.size() == 1);  // the trailing edge; the leading edge is smooth
  CHECK(m.fan_sizes[0] >= 5);
  CHECK(q.max_thickness_jump <= 1.3 + 1e-12);
  CHECK(q.max_thickness == Approx(0.05).epsilon(1e-9));
  REQUIRE(m.fronts.size() == 1);
  CHECK(m.fronts[0].closed);
}

TEST_CASE("30P30N: all three elements, h1 1e-5, growth 1.15, thickness 0.02", "[layers]") {
  const std::vector<std::string> names = {"main_cove",  "main_cove_wall", "main_lower", "main_upper", "main_te",
                                          "flap_lower", "flap_upper",     "flap_te",    "slat_te",    "slat_cove",
                                          "slat_upper", "bottom",         "right",      "top",        "left"};
  const Geometry g = case_geometry("30p30n", names);
  LayerSettings s;
  s.first_height = 1e-5;
  s.growth = 1.15;
  s.thickness = 0.02;
  const std::vector<std::string> walls(names.begin(), names.begin() + 11);
  const LayerMesh m = build_boundary_layers(g, curves_by_name(g, walls, "test"), s);
  const LayerMeasures q = measure_layers(m, s.first_height);
  CHECK(q.first_height_within_2pct >= 0.99);
  CHECK(q.inverted_cells == 0);
  CHECK(q.growth_max <= 1.25 * 1.15 + 1e-12);
  CHECK(q.max_thickness_jump <= 1.3 + 1e-12);  // slat cove and both gaps included
  CHECK(m.fronts.size() == 3);
  // Every element keeps a layer: none shrinks below a tenth of the thickness.
  CHECK(q.min_thickness >= 0.1 * s.thickness);
}

TEST_CASE("the fronts bound a valid core geometry and the cells tile the layer region exactly", "[layers]") {
  const std::vector<std::string> names = {"main_cove",  "main_cove_wall", "main_lower", "main_upper", "main_te",
                                          "flap_lower", "flap_upper",     "flap_te",    "slat_te",    "slat_cove",
                                          "slat_upper", "bottom",         "right",      "top",        "left"};
  struct Case {
    std::string dir;
    std::vector<std::string> names;
    std::vector<std::string> walls;
    double h1, growth, thickness;
  };
  const std::vector<Case> cases = {
      {"naca0012", {"upper", "lower", "bottom", "right", "top", "left"}, {"upper", "lower"}, 1e-5, 1.2, 0.05},
      {"30p30n", names, std::vector<std::string>(names.begin(), names.begin() + 11), 1e-5, 1.15, 0.02}};
  for (const Case& c : cases) {
    INFO(c.dir);
    const Geometry g = case_geometry(c.dir, c.names);
    LayerSettings s;
    s.first_height = c.h1;
    s.growth = c.growth;
    s.thickness = c.thickness;
    const std::vector<int> walls = curves_by_name(g, c.walls, "test");
    const LayerMesh m = build_boundary_layers(g, walls, s);
    const Geometry core = build_geometry(front_curves(g, walls, m));  // throws on crossing curves
    double cells = 0.0;
    for (const LayerCell& cell : m.cells) {
      const int k = cell.triangle() ? 3 : 4;
      for (int i = 0; i < k; ++i) cells += 0.5 * cross(m.nodes[cell.v[i]], m.nodes[cell.v[(i + 1) % k]]);
    }
    // No overlap and no hole: the cells' area is the domain's minus the core's.
    CHECK(cells == Approx(g.area - core.area).epsilon(1e-9));
    CHECK(cells > 0.0);
  }
}

namespace {

// The largest angle (degrees) of the cells that are not in a fan.
double max_angle_outside_fans(const LayerMesh& m) {
  double lo = 1.0;
  for (const LayerCell& c : m.cells) {
    if (c.kind == LayerCellKind::Fan) continue;
    const int k = c.triangle() ? 3 : 4;
    for (int i = 0; i < k; ++i) {
      const Vec2 u = m.nodes[c.v[(i + 1) % k]] - m.nodes[c.v[i]], w = m.nodes[c.v[(i + k - 1) % k]] - m.nodes[c.v[i]];
      lo = std::min(lo, dot(u, w) / (norm(u) * norm(w)));
    }
  }
  return std::acos(lo) * 180.0 / std::numbers::pi;
}

}  // namespace

TEST_CASE("NACA 0012 in triangles: no angle above 95 degrees outside the fans", "[layers]") {
  // The nose's vertices turn by up to 26 degrees; a bisector ray there is 13 degrees off both
  // segments' normals, and the split of its thin wall cells has an angle of about 103 degrees.
  // With the rays kept within 5 degrees of their normals (fans where the wall turns more), as the
  // pipeline builds triangles, every split cell outside the fans stays within about 95 degrees.
  const Geometry g = case_geometry("naca0012", {"upper", "lower", "bottom", "right", "top", "left"});
  LayerSettings s;
  s.first_height = 1e-5;
  s.growth = 1.2;
  s.thickness = 0.05;
  s.split_quads = true;
  s.fan_elements_per_pi = fan_elements_matching_core(s.growth);
  const std::vector<int> walls = curves_by_name(g, {"upper", "lower"}, "test");
  s.max_ray_tilt_deg = 0.0;
  CHECK(max_angle_outside_fans(build_boundary_layers(g, walls, s)) > 100.0);
  s.max_ray_tilt_deg = 5.0;
  const LayerMesh m = build_boundary_layers(g, walls, s);
  const LayerMeasures q = measure_layers(m, s.first_height);
  CHECK(max_angle_outside_fans(m) <= 95.5);
  CHECK(q.quads == 0);
  CHECK(q.first_height_within_2pct == 1.0);
  CHECK(q.inverted_cells == 0);
  CHECK(q.growth_max <= 1.25 * 1.2 + 1e-12);
  CHECK(q.max_thickness_jump <= 1.3 + 1e-12);
  CHECK(m.fan_sizes.size() >= 2);  // the trailing edge and the nose
}
