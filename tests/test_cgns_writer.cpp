// The CGNS writer: a triangle mesh with regions and a layered mesh written through write_mesh and
// write_mixed_mesh, read back with the CGNS library's own read calls (counts, coordinates,
// connectivity, element types, boundary conditions, families); names, errors, atomicity.
#include <catch2/catch.hpp>

#include <cgnslib.h>

#include <filesystem>
#include <string>
#include <vector>

#include "core/errors.hpp"
#include "io/cgns_writer.hpp"
#include "io/mesh_formats.hpp"
#include "io/mixed_mesh.hpp"
#include "run_pdmesh.hpp"
#include "mixed_square.hpp"
#include "temp_files.hpp"

using namespace pdmesh;
namespace fs = std::filesystem;

namespace {

// What the file holds, read with the mid-level library.
struct CgnsSection {
  std::string name;
  ElementType_t type = ElementTypeNull;
  cgsize_t start = 0, end = 0;
  std::vector<cgsize_t> conn;
};
struct CgnsBoco {
  std::string name, family;
  BCType_t type = BCTypeNull;
  PointSetType_t set = PointSetTypeNull;
  GridLocation_t location = GridLocationNull;
  std::vector<cgsize_t> points;
};
struct CgnsFamily {
  std::string name, physical;
  BCType_t bc = BCTypeNull;
};
struct CgnsContent {
  int cell_dim = 0, phys_dim = 0;
  cgsize_t vertices = 0, cells = 0;
  std::vector<double> x, y;
  std::vector<CgnsSection> sections;
  std::vector<CgnsBoco> bocos;
  std::vector<CgnsFamily> families;
  const CgnsSection& section(const std::string& name) const {
    for (const auto& s : sections)
      if (s.name == name) return s;
    FAIL("no section " << name);
    return sections.front();
  }
  std::vector<double> region;  // the FlowSolution "Regions" field "region"
  const CgnsFamily& family(const std::string& name) const {
    for (const auto& f : families)
      if (f.name == name) return f;
    FAIL("no family " << name);
    return families.front();
  }
  const CgnsBoco& boco(const std::string& name) const {
    for (const auto& b : bocos)
      if (b.name == name) return b;
    FAIL("no BC " << name);
    return bocos.front();
  }
};

#define CG(call) REQUIRE((call) == CG_OK)

CgnsContent read_cgns(const fs::path& path) {
  CgnsContent c;
  int fn = 0;
  REQUIRE(cg_open(path.c_str(), CG_MODE_READ, &fn) == CG_OK);
  int nbases = 0, nzones = 0;
  CG(cg_nbases(fn, &nbases));
  REQUIRE(nbases == 1);
  char name[64];
  CG(cg_base_read(fn, 1, name, &c.cell_dim, &c.phys_dim));
  CG(cg_nzones(fn, 1, &nzones));
  REQUIRE(nzones == 1);
  ZoneType_t zt;
  CG(cg_zone_type(fn, 1, 1, &zt));
  REQUIRE(zt == Unstructured);
  cgsize_t size[3];
  CG(cg_zone_read(fn, 1, 1, name, size));
  c.vertices = size[0];
  c.cells = size[1];
  int ncoords = 0;
  CG(cg_ncoords(fn, 1, 1, &ncoords));
  REQUIRE(ncoords == 2);
  cgsize_t lo = 1, hi = c.vertices;
  c.x.resize(static_cast<std::size_t>(c.vertices));
  c.y.resize(static_cast<std::size_t>(c.vertices));
  CG(cg_coord_read(fn, 1, 1, "CoordinateX", RealDouble, &lo, &hi, c.x.data()));
  CG(cg_coord_read(fn, 1, 1, "CoordinateY", RealDouble, &lo, &hi, c.y.data()));
  int nsections = 0;
  CG(cg_nsections(fn, 1, 1, &nsections));
  for (int s = 1; s <= nsections; ++s) {
    CgnsSection sec;
    int nbndry = 0, parent = 0;
    CG(cg_section_read(fn, 1, 1, s, name, &sec.type, &sec.start, &sec.end, &nbndry, &parent));
    sec.name = name;
    cgsize_t data = 0;
    CG(cg_ElementDataSize(fn, 1, 1, s, &data));
    sec.conn.resize(static_cast<std::size_t>(data));
    CG(cg_elements_read(fn, 1, 1, s, sec.conn.data(), nullptr));
    c.sections.push_back(std::move(sec));
  }
  int nsols = 0;
  CG(cg_nsols(fn, 1, 1, &nsols));
  REQUIRE(nsols == 1);
  GridLocation_t where;
  CG(cg_sol_info(fn, 1, 1, 1, name, &where));
  CHECK(std::string(name) == "Regions");
  CHECK(where == CellCenter);
  c.region.resize(static_cast<std::size_t>(c.cells));
  cgsize_t one = 1, cells = c.cells;
  CG(cg_field_read(fn, 1, 1, 1, "region", RealDouble, &one, &cells, c.region.data()));
  int nbocos = 0;
  CG(cg_nbocos(fn, 1, 1, &nbocos));
  for (int b = 1; b <= nbocos; ++b) {
    CgnsBoco bc;
    cgsize_t npts = 0, normal_list = 0;
    int normal_index = 0, ndataset = 0;
    DataType_t normal_type;
    CG(cg_boco_info(fn, 1, 1, b, name, &bc.type, &bc.set, &npts, &normal_index, &normal_list, &normal_type, &ndataset));
    bc.name = name;
    CG(cg_boco_gridlocation_read(fn, 1, 1, b, &bc.location));
    bc.points.resize(static_cast<std::size_t>(npts));
    CG(cg_boco_read(fn, 1, 1, b, bc.points.data(), nullptr));
    CG(cg_goto(fn, 1, "Zone_t", 1, "ZoneBC_t", 1, "BC_t", b, "end"));
    CG(cg_famname_read(name));
    bc.family = name;
    c.bocos.push_back(std::move(bc));
  }
  int nfamilies = 0;
  CG(cg_nfamilies(fn, 1, &nfamilies));
  for (int f = 1; f <= nfamilies; ++f) {
    CgnsFamily fam;
    int nfambc = 0, ngeo = 0, nnames = 0;
    CG(cg_family_read(fn, 1, f, name, &nfambc, &ngeo));
    fam.name = name;
    REQUIRE(nfambc == 1);
    char bcname[64];
    CG(cg_fambc_read(fn, 1, f, 1, bcname, &fam.bc));
    CG(cg_nfamily_names(fn, 1, f, &nnames));
    REQUIRE(nnames == 1);
    char node[64], value[64];
    CG(cg_family_name_read(fn, 1, f, 1, node, value));
    fam.physical = value;
    c.families.push_back(std::move(fam));
  }
  CG(cg_close(fn));
  return c;
}

std::vector<cgsize_t> one_based(std::initializer_list<int> v) {
  std::vector<cgsize_t> out;
  for (int i : v) out.push_back(i + 1);
  return out;
}

// A unit square of four triangles around its centre (point 4), in two regions (left: attribute 2,
// named "left side"; right: 7 without a name), curves bottom (one edge), right, top, left, and a
// curve "cut" without edges.
Mesh two_regions() {
  Mesh m;
  m.points = {{0, 0}, {1, 0}, {1, 1}, {0, 1}, {0.5, 0.5}};
  m.triangles = {{0, 1, 4}, {1, 2, 4}, {2, 3, 4}, {3, 0, 4}};
  m.region = {2, 7, 7, 2};
  m.region_names = {{2.0, "left side"}};
  m.curve_names = {"bottom", "right", "top", "left", "cut"};
  m.boundary_edges = {{0, 1, 0}, {1, 2, 1}, {2, 3, 2}, {3, 0, 3}};
  return m;
}

}  // namespace

TEST_CASE("a triangle mesh's CGNS file reads back with the CGNS library: points, cells, regions, boundary conditions",
          "[io][cgns]") {
  const fs::path dir = pdmesh_test::fresh_dir("cgns_triangles");
  const Mesh m = two_regions();
  MeshWriteOptions options;
  options.walls = {"top", "cut"};  // "cut" has no edges: its family alone says wall
  const auto written = write_mesh(m, dir, "m", {"cgns"}, options);
  REQUIRE(written == std::vector<fs::path>{dir / "m.cgns"});
  CHECK(pdmesh_test::entries(dir) == 1);  // no temporary left
  const CgnsContent c = read_cgns(dir / "m.cgns");
  CHECK(c.cell_dim == 2);
  CHECK(c.phys_dim == 2);
  CHECK(c.vertices == 5);
  CHECK(c.cells == 4);
  for (std::size_t i = 0; i < m.points.size(); ++i) {
    CHECK(c.x[i] == m.points[i].x);  // doubles, bit for bit
    CHECK(c.y[i] == m.points[i].y);
  }
  // The regions in ascending attribute order, each its triangles in mesh order, counter-clockwise.
  REQUIRE(c.sections.size() == 6);
  CHECK(c.sections[0].name == "left_side");
  CHECK(c.sections[0].type == TRI_3);
  CHECK(c.sections[0].start == 1);
  CHECK(c.sections[0].end == 2);
  CHECK(c.sections[0].conn == one_based({0, 1, 4, 3, 0, 4}));
  CHECK(c.sections[1].name == "region_7");
  CHECK(c.sections[1].start == 3);
  CHECK(c.sections[1].end == 4);
  CHECK(c.sections[1].conn == one_based({1, 2, 4, 2, 3, 4}));
  // Then a BAR_2 section per curve with edges; "cut" has none.
  const char* curves[] = {"bottom", "right", "top", "left"};
  for (int k = 0; k < 4; ++k) {
    const CgnsSection& s = c.sections[static_cast<std::size_t>(2 + k)];
    CHECK(s.name == curves[k]);
    CHECK(s.type == BAR_2);
    CHECK(s.start == 5 + k);
    CHECK(s.end == 5 + k);
    const auto& e = m.boundary_edges[static_cast<std::size_t>(k)];
    CHECK(s.conn == std::vector<cgsize_t>{e.a + 1, e.b + 1});
  }
  // One BC per curve with edges (its BAR_2 elements), then one per region (its cells).
  REQUIRE(c.bocos.size() == 6);
  for (const auto& b : c.bocos) CHECK(b.type == FamilySpecified);  // the family says wall or not
  CHECK(c.boco("top").set == PointList);
  CHECK(c.boco("top").location == EdgeCenter);
  CHECK(c.boco("top").points == std::vector<cgsize_t>{7});
  CHECK(c.boco("top").family == "top");
  CHECK(c.boco("region_7").location == CellCenter);
  CHECK(c.boco("region_7").set == PointRange);
  CHECK(c.boco("region_7").points == std::vector<cgsize_t>{3, 4});
  CHECK(c.boco("left_side").points == std::vector<cgsize_t>{1, 2});
  CHECK(c.region == std::vector<double>{0, 0, 1, 1});  // per cell in file order: its region's index
  // A family per curve (also "cut") and per region, each naming itself as its physical group.
  REQUIRE(c.families.size() == 7);
  std::vector<std::string> families;
  for (const auto& f : c.families) {
    families.push_back(f.name);
    CHECK(f.physical == f.name);
    CHECK(f.bc == (f.name == "top" || f.name == "cut" ? BCWall : BCTypeNull));
  }
  std::sort(families.begin(), families.end());
  CHECK(families == std::vector<std::string>{"bottom", "cut", "left", "left_side", "region_7", "right", "top"});
}

TEST_CASE("a mesh without regions is one section 'domain', and kept physical groups are one BC each", "[io][cgns]") {
  Mesh m = two_regions();
  m.region.clear();
  m.region_names.clear();
  // Curves bottom and left in group 5 "walls": one BAR_2 section and BC over both, in edge order.
  m.curve_groups = {{5, "walls", {0, 3}}};
  const fs::path dir = pdmesh_test::fresh_dir("cgns_groups");
  MeshWriteOptions options;
  options.walls = {"left"};  // one of the group's curves makes the group a wall
  write_mesh(m, dir, "m", {"cgns"}, options);
  const CgnsContent c = read_cgns(dir / "m.cgns");
  REQUIRE(c.sections.size() >= 2);
  CHECK(c.sections[0].name == "domain");
  CHECK(c.sections[0].end == 4);
  const CgnsSection& walls = c.section("walls");
  CHECK(walls.type == BAR_2);
  CHECK(walls.conn == one_based({0, 1, 3, 0}));
  CHECK(c.family("walls").bc == BCWall);
  CHECK(c.boco("walls").points.size() == 2);
  CHECK(c.family("right").bc == BCTypeNull);
}

TEST_CASE("a layered mesh's CGNS file: TRI_3 and QUAD_4 sections, the layer a region, wall BCs", "[io][cgns]") {
  const fs::path dir = pdmesh_test::fresh_dir("cgns_layers");
  const MixedMesh m = pdmesh_test::mixed_square();
  const auto written = write_mixed_mesh(m, dir, "m", {"cgns"}, nullptr, {"bottom"});
  REQUIRE(written == std::vector<fs::path>{dir / "m.cgns"});
  const CgnsContent c = read_cgns(dir / "m.cgns");
  CHECK(c.vertices == 6);
  CHECK(c.cells == 3);
  REQUIRE(c.sections.size() == 6);
  CHECK(c.sections[0].name == "domain");
  CHECK(c.sections[0].type == TRI_3);
  CHECK(c.sections[0].conn == one_based({1, 2, 3, 1, 3, 4}));
  CHECK(c.sections[1].name == "boundary_layer");
  CHECK(c.sections[1].type == QUAD_4);
  CHECK(c.sections[1].start == 3);
  CHECK(c.sections[1].conn == one_based({0, 1, 4, 5}));
  CHECK(c.section("bottom").conn == one_based({0, 1, 1, 2}));
  CHECK(c.section("top").start == 7);
  CHECK(c.section("top").end == 8);
  CHECK(c.family("bottom").bc == BCWall);
  CHECK(c.boco("bottom").points == std::vector<cgsize_t>{4, 5});
  CHECK(c.family("top").bc == BCTypeNull);
  CHECK(c.region == std::vector<double>{0, 0, 1});
  CHECK(c.boco("boundary_layer").points == std::vector<cgsize_t>{3, 3});
  CHECK(c.boco("boundary_layer").location == CellCenter);
}

TEST_CASE("a layered mesh with kept groups and regions: one BC per group, the core's region and the layer's",
          "[io][cgns]") {
  const fs::path dir = pdmesh_test::fresh_dir("cgns_layer_tags");
  MixedMesh m = pdmesh_test::mixed_square();
  m.curve_groups = {{12, "sides", {1, 3}}, {4, "floor", {0}}};
  m.region = {3.0, 3.0, 3.0};
  m.region_names = {{3.0, "core"}};
  write_mixed_mesh(m, dir, "m", {"cgns"}, nullptr, {"floor"});
  const CgnsContent c = read_cgns(dir / "m.cgns");
  REQUIRE(c.sections.size() >= 2);
  CHECK(c.sections[0].name == "core");
  CHECK(c.sections[0].type == TRI_3);
  CHECK(c.sections[1].name == "boundary_layer");
  CHECK(c.sections[1].type == QUAD_4);
  // The groups in tag order, then the curve in no group; 'sides' holds both of its curves' edges.
  CHECK(c.section("floor").conn == one_based({0, 1, 1, 2}));
  CHECK(c.section("sides").conn.size() == 4);
  CHECK(c.section("top").conn.size() == 4);
  for (const auto& section : c.sections) CHECK(section.name != "right");
  CHECK(c.family("floor").bc == BCWall);
  CHECK(c.family("sides").bc == BCTypeNull);
  CHECK(c.region == std::vector<double>{0, 0, 1});  // file order: the core's triangles, then the layer's quad
  CHECK(c.boco("core").location == CellCenter);
}

TEST_CASE("CGNS names: at most 32 characters, no '/', unique among siblings", "[io][cgns]") {
  MixedMesh m = pdmesh_test::mixed_square();
  m.curve_names = {"a/very/long/curve/name/that/goes/on/and/on", "a/very/long/curve/name/that/goes/on/and/on/too",
                   "domain", "ZoneBC"};
  const CgnsLayout layout = cgns_layout(m, {});
  std::vector<std::string> names;
  for (const auto& s : layout.sections) names.push_back(s.name);
  CHECK(names == std::vector<std::string>{"domain", "boundary_layer", "a_very_long_curve_name_that_goes",
                                          "a_very_long_curve_name_that_go_2", "domain_2", "ZoneBC_2"});
  for (const auto& n : names) CHECK(n.size() <= 32);
}

TEST_CASE("a CGNS write that fails names the file and the library's message and leaves nothing", "[io][cgns]") {
  const fs::path dir = pdmesh_test::fresh_dir("cgns_fail");
  // A directory where the file should go: the library cannot create the file (the temporary is fine,
  // the rename fails) or, in a missing directory, cannot open it.
  const fs::path missing = dir / "no_such_dir" / "m.cgns";
  try {
    write_cgns(pdmesh_test::mixed_square(), missing, {});
    FAIL("no error");
  } catch (const InputError& e) {
    const std::string what = e.what();
    CHECK_THAT(what, Catch::Contains(missing.string() + ": CGNS library failed opening the file for writing: "));
  }
  CHECK(pdmesh_test::entries(dir) == 0);
  // A cell with a point out of range is refused before the file is opened.
  MixedMesh bad = pdmesh_test::mixed_square();
  bad.cells[1][2] = 9;
  CHECK_THROWS_WITH(write_cgns(bad, dir / "m.cgns", {}), Catch::Contains("point 9 (of 6)"));
  CHECK(pdmesh_test::entries(dir) == 0);
}

TEST_CASE("pdmesh mesh --formats cgns writes mesh.cgns with the run's cells and curves, layered or not",
          "[io][cgns][cli]") {
  for (const char* name : {"two_regions", "layered"}) {
    INFO(name);
    const fs::path out = pdmesh_test::fresh_path(std::string("cgns_cli_") + name);
    const std::string case_file = std::string(PDMESH_SOURCE_DIR) + "/tests/data/interop/" + name + ".toml";
    const auto r = pdmesh_test::run_pdmesh("mesh '" + case_file + "' --formats cgns,su2 --out '" + out.string() + "'");
    REQUIRE(r.status == 0);
    CHECK_THAT(r.output, Catch::Contains("mesh.cgns"));
    // The SU2 file of the same run holds the same mesh.
    MeshReadReport report;
    SurfaceCells cells;
    const Mesh su2 = read_mesh(out / "mesh.su2", report, &cells);
    const CgnsContent c = read_cgns(out / "mesh.cgns");
    CHECK(static_cast<std::size_t>(c.vertices) == su2.points.size());
    CHECK(static_cast<std::size_t>(c.cells) == su2.triangles.size() + cells.quads.size());
    std::size_t bars = 0, quads = 0;
    for (const auto& s : c.sections) {
      bars += s.type == BAR_2 ? s.conn.size() / 2 : 0;
      quads += s.type == QUAD_4 ? s.conn.size() / 4 : 0;
    }
    CHECK(bars == su2.boundary_edges.size());
    CHECK(quads == cells.quads.size());
    const bool layered = std::string(name) == "layered";
    CHECK((quads > 0) == layered);
    // A BC per curve (each has edges here) and per region.
    CHECK(c.bocos.size() == su2.curve_names.size() + 2);
  }
}
