// A layered run keeps the input's physical groups and regions: the Gmsh channel and block of
// tests/data/layer_tags (wall 5, farfield 7 and slip 8 over two curves each, block 9; fluid 11 and
// solid 22) with boundary layers on the wall, through the mixed-cell writers (MSH 4.1, VTU, SU2, Medit) and read back;
// and the writers' rules on small mixed meshes built here, a mesh without groups or regions written as
// before (curve c with tag c + 1, "domain" and "boundary_layer").
#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "io/medit_writer.hpp"
#include "io/mesh_formats.hpp"
#include "io/mesh_io_common.hpp"
#include "io/mixed_mesh.hpp"
#include "io/openfoam_writer.hpp"
#include "msh_physical_names.hpp"
#include "run_pdmesh.hpp"
#include "temp_files.hpp"

using namespace pdmesh;
namespace fs = std::filesystem;
using pdmesh_test::physical_names;
using pdmesh_test::run_pdmesh;

namespace {

const std::string kData = std::string(PDMESH_SOURCE_DIR) + "/tests/data/";

// The lines of `text` that start with `prefix`.
std::vector<std::string> lines_starting(const std::string& text, const std::string& prefix) {
  std::istringstream in(text);
  std::vector<std::string> out;
  std::string line;
  while (std::getline(in, line))
    if (line.rfind(prefix, 0) == 0) out.push_back(line);
  return out;
}

// The channel with layers on the wall, written once per process.
const fs::path& layered_run() {
  static const fs::path out = [] {
    const fs::path dir = pdmesh_test::fresh_path("layer_tags");
    const auto run =
        run_pdmesh("mesh '" + kData + "layer_tags/case.toml' --out '" + dir.string() + "' --device host -q");
    INFO(run.output);
    REQUIRE(run.status == 0);
    return dir;
  }();
  return out;
}

// {tag: name} of a mesh's curve groups.
std::map<long long, std::string> groups_of(const Mesh& m) {
  std::map<long long, std::string> out;
  for (const CurveGroupTag& g : m.curve_groups) out[g.tag] = g.name;
  return out;
}

const std::map<long long, std::string> kGroups = {{5, "wall"}, {7, "farfield"}, {8, "slip"}, {9, "block"}};

// Where an edge lies: the group the channel's geometry puts it in (0 for none of them).
long long group_at(Vec2 a, Vec2 b) {
  // The wall's nodes lie on the input's polygon of the circle, within its sagitta of the circle.
  const auto on_wall = [](Vec2 p) { return std::abs(std::hypot(p.x, p.y) - 0.25) < 0.01; };
  const auto near = [](double u, double v) { return std::abs(u - v) < 1e-9; };
  if (std::min(a.x, b.x) >= 2.0) return 9;
  if (on_wall(a) && on_wall(b)) return 5;
  if (near(a.x, b.x) && (near(a.x, -1.5) || near(a.x, 1.5))) return 7;
  if (near(a.y, b.y) && (near(a.y, -1.0) || near(a.y, 1.0))) return 8;
  return 0;
}

// Every boundary edge of `m` lies where its curve's group says.
void check_edges_in_groups(const Mesh& m) {
  std::map<int, long long> tag_of_curve;
  for (const CurveGroupTag& g : m.curve_groups)
    for (const int c : g.curves) tag_of_curve[c] = g.tag;
  std::map<long long, std::size_t> per_group;
  for (const BoundaryEdge& e : m.boundary_edges) {
    const long long want = group_at(m.points[static_cast<std::size_t>(e.a)], m.points[static_cast<std::size_t>(e.b)]);
    INFO("edge " << e.a << "-" << e.b << " on curve " << e.curve);
    REQUIRE(tag_of_curve.count(e.curve) == 1);
    CHECK(tag_of_curve[e.curve] == want);
    ++per_group[want];
  }
  CHECK(per_group.size() == 4);
  CHECK(per_group[5] >= 8);
}

}  // namespace

TEST_CASE("a layered run of a Gmsh file keeps its groups and regions in MSH 4.1, read back the same") {
  const std::string msh = pdmesh_test::slurp(layered_run() / "mesh.msh");
  const std::vector<std::string> names = physical_names(msh);
  REQUIRE(names.size() == 8);
  CHECK(names[0] == "7");
  CHECK(std::vector<std::string>(names.begin() + 1, names.begin() + 7) ==
        std::vector<std::string>{"1 5 \"wall\"", "1 7 \"farfield\"", "1 8 \"slip\"", "1 9 \"block\"", "2 11 \"fluid\"",
                                 "2 22 \"solid\""});
  // The layer: 6 curves + 1 + 2 core surfaces.
  CHECK(names[7] == "2 9 \"boundary_layer\"");

  MeshReadReport report;
  SurfaceCells cells;
  cells.region = kLayerRegion;
  const Mesh back = read_mesh(layered_run() / "mesh.msh", report, &cells);
  CHECK(groups_of(back) == kGroups);
  check_edges_in_groups(back);
  REQUIRE(cells.region_found);
  REQUIRE(!cells.quads.empty());
  for (const auto q : cells.quad_in_region) CHECK(q == 1);
  // The core's triangles keep their region: fluid in the channel, solid in the block.
  REQUIRE(back.region.size() == back.triangles.size());
  std::size_t core = 0;
  for (std::size_t t = 0; t < back.triangles.size(); ++t) {
    if (cells.triangle_in_region[t] != 0) continue;
    const auto& v = back.triangles[t];
    const double x = (back.points[v[0]].x + back.points[v[1]].x + back.points[v[2]].x) / 3.0;
    CHECK(back.region[t] == (x < 1.75 ? 11.0 : 22.0));
    ++core;
  }
  CHECK(core > 100);
  CHECK(region_label(back, 11.0) == "fluid");
  CHECK(region_label(back, 22.0) == "solid");
  // A picture of the file filled by region (pdmesh quality --color-by region) shows its surfaces.
  MixedMesh mixed = mixed_mesh_of(back, cells);
  add_file_regions(mixed, back);
  Mesh drawn = triangulated(mixed);
  add_layer_regions(mixed, drawn);
  std::vector<std::string> drawn_names;
  for (const auto& r : drawn.region_names) drawn_names.push_back(r.name);
  CHECK(drawn_names == std::vector<std::string>{"fluid", "solid", "boundary_layer"});
  REQUIRE(drawn.region.size() == drawn.triangles.size());
}

TEST_CASE("a layered run of a Gmsh file keeps its groups in SU2, VTU and Medit") {
  SECTION("SU2: one marker per group, over all its curves' edges") {
    const std::string su2 = pdmesh_test::slurp(layered_run() / "mesh.su2");
    CHECK(lines_starting(su2, "NMARK=") == std::vector<std::string>{"NMARK= 4"});
    CHECK(lines_starting(su2, "MARKER_TAG=") == std::vector<std::string>{"MARKER_TAG= wall", "MARKER_TAG= farfield",
                                                                         "MARKER_TAG= slip", "MARKER_TAG= block"});
    const Mesh m = read_mesh(layered_run() / "mesh.su2");
    CHECK(m.curve_names == std::vector<std::string>{"wall", "farfield", "slip", "block"});
  }
  SECTION("VTU: the groups as field data, every cell's region as cell data, read back as the groups") {
    const Mesh m = read_mesh(layered_run() / "mesh.vtu");
    CHECK(groups_of(m) == kGroups);
    check_edges_in_groups(m);
    REQUIRE(m.region.size() == m.triangles.size());
    CHECK(std::set<double>(m.region.begin(), m.region.end()) == std::set<double>{11.0, 22.0});
    CHECK(region_label(m, 11.0) == "fluid");
    const std::string vtu = pdmesh_test::slurp(layered_run() / "mesh.vtu");
    CHECK(vtu.find("Name=\"boundary_layer\"") != std::string::npos);
    CHECK(vtu.find("Name=\"region\"") != std::string::npos);
  }
  SECTION("Medit: edge references are the group tags, cells the region tags and the layer's own") {
    const std::string medit = pdmesh_test::slurp(layered_run() / "mesh.mesh");
    CHECK(medit.find("# ref 5: curve wall\n# ref 7: curve farfield\n# ref 8: curve slip\n# ref 9: curve block\n"
                     "# ref 11: region fluid\n# ref 22: region solid\n# ref 3: region boundary_layer\n") !=
          std::string::npos);
    const std::vector<std::string> layer = lines_starting(medit, "# ref ");
    REQUIRE(layer.size() == 7);
    CHECK(layer[6].find(": region boundary_layer") != std::string::npos);
    const Mesh m = read_mesh(layered_run() / "mesh.mesh");
    CHECK(std::set<double>(m.region.begin(), m.region.end()).count(11.0) == 1);
    CHECK(std::set<double>(m.region.begin(), m.region.end()).count(22.0) == 1);
  }
}

namespace {

// Two core triangles (regions 3 and 0.5) and a layer quad under them, on three curves: the quad's
// bottom "wall", the sides "side" and "side_2", and the top; `groups` puts the sides in one group.
MixedMesh small_mixed(bool groups, bool regions) {
  MixedMesh m;
  m.points = {{0, 0}, {2, 0}, {2, 1}, {0, 1}, {1, 2}};
  m.cells = {{3, 2, 4, -1}, {0, 1, 2, 3}};
  m.layer = {0, 1};
  m.curve_names = {"wall", "side", "side_2", "top"};
  m.boundary_edges = {{0, 1, 0}, {1, 2, 1}, {3, 0, 2}, {2, 4, 3}, {4, 3, 3}};
  if (groups) m.curve_groups = {{12, "sides", {1, 2}}, {4, "wall", {0}}};
  if (regions) {
    m.region = {3.0, 3.0};
    m.region_names = {{3.0, "core"}};
  }
  return m;
}

}  // namespace

TEST_CASE("mixed writers without groups or regions number as before: curve c + 1, domain, boundary_layer") {
  const MixedMesh m = small_mixed(false, false);
  CHECK(physical_names(mixed_msh41_string(m)) == std::vector<std::string>{"6", "1 1 \"wall\"", "1 2 \"side\"",
                                                                          "1 3 \"side_2\"", "1 4 \"top\"",
                                                                          "2 5 \"domain\"", "2 6 \"boundary_layer\""});
  const std::string medit = mixed_medit_string(m);
  CHECK(medit.find("# ref 1: curve wall\n# ref 2: curve side\n# ref 3: curve side_2\n# ref 4: curve top\n"
                   "# ref 1: region boundary_layer\n") != std::string::npos);
  CHECK(medit.find("Triangles\n1\n4 3 5 0\nQuadrilaterals\n1\n1 2 3 4 1\n") != std::string::npos);
  CHECK(lines_starting(mixed_su2_string(m), "MARKER_TAG=") ==
        std::vector<std::string>{"MARKER_TAG= wall", "MARKER_TAG= side", "MARKER_TAG= side_2", "MARKER_TAG= top"});
  CHECK(mixed_vtu_string(m).find("curve_tags") == std::string::npos);
  CHECK(mixed_vtu_string(m).find("Name=\"region\"") == std::string::npos);
}

TEST_CASE("mixed writers with groups and regions: the group tags, the region's tag, the layer's next free one") {
  const MixedMesh m = small_mixed(true, true);
  // Curves: wall 4, sides 12 over two curves, top the first free number, 1. Surfaces from 5: the core's
  // region 3 is its own tag, the layer takes 5 + 1.
  const std::string msh = mixed_msh41_string(m);
  CHECK(physical_names(msh) == std::vector<std::string>{"5", "1 1 \"top\"", "1 4 \"wall\"", "1 12 \"sides\"",
                                                        "2 3 \"core\"", "2 6 \"boundary_layer\""});
  CHECK(msh.find("$Entities\n0 4 2 0\n") != std::string::npos);
  const MixedSurfaces s = mixed_surfaces(m, 5);
  CHECK(s.core.tags == std::vector<long long>{3});
  CHECK(s.layer_tag == 6);
  CHECK(s.of_cell == std::vector<int>{0, 1});
  // From 1 (Medit) the layer's 2 would be free, the region 3 is its own.
  const std::string medit = mixed_medit_string(m);
  CHECK(medit.find("# ref 1: curve top\n# ref 4: curve wall\n# ref 12: curve sides\n# ref 3: region core\n"
                   "# ref 2: region boundary_layer\n") != std::string::npos);
  CHECK(medit.find("Triangles\n1\n4 3 5 3\nQuadrilaterals\n1\n1 2 3 4 2\n") != std::string::npos);
  CHECK(medit.find("Edges\n5\n1 2 4\n2 3 12\n4 1 12\n3 5 1\n5 4 1\n") != std::string::npos);
  const std::string su2 = mixed_su2_string(m);
  CHECK(su2.find("NMARK= 3\nMARKER_TAG= top\nMARKER_ELEMS= 2\n3 2 4\n3 4 3\nMARKER_TAG= wall\nMARKER_ELEMS= 1\n3 0 1\n"
                 "MARKER_TAG= sides\nMARKER_ELEMS= 2\n3 1 2\n3 3 0\n") != std::string::npos);
  const std::string vtu = mixed_vtu_string(m);
  CHECK(vtu.find("Name=\"curve_tags\"") != std::string::npos);
  CHECK(vtu.find("Name=\"region\" format=\"ascii\">\n3\n3\n") != std::string::npos);
  // OpenFOAM: the patches by group, the regions as cellZones.
  const OpenFoamZones zones{{"core", "boundary_layer"}, s.of_cell};
  const OpenFoamFiles foam = openfoam_files(m, {"wall"}, m.curve_groups, &zones);
  CHECK(foam.boundary.find("sides") != std::string::npos);
  CHECK(foam.boundary.find("side_2") == std::string::npos);
}

TEST_CASE("a layered run writes OpenFOAM patches per group") {
  const fs::path dir = pdmesh_test::fresh_path("layer_tags_foam");
  const auto run = run_pdmesh("mesh '" + kData + "layer_tags/case.toml' --out '" + dir.string() +
                              "' --formats openfoam --device host -q");
  INFO(run.output);
  REQUIRE(run.status == 0);
  const std::string boundary = pdmesh_test::slurp(openfoam_polymesh_dir(dir, "mesh") / "boundary");
  for (const char* patch : {"wall", "farfield", "slip", "block"}) CHECK(boundary.find(patch) != std::string::npos);
  CHECK(boundary.find("farfield_2") == std::string::npos);
  CHECK(boundary.find("slip_2") == std::string::npos);
  const std::string zones = pdmesh_test::slurp(openfoam_polymesh_dir(dir, "mesh") / "cellZones");
  for (const char* zone : {"fluid", "solid", "boundary_layer"}) CHECK(zones.find(zone) != std::string::npos);
}
