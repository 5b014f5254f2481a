// A mesh file as the geometry (io/mesh_geometry): meshes built here turned into loops, curves named
// by the file, groups for a name on separate stretches, constraints between regions, quads and Medit
// corners, and the refusals; a run's own mesh files in every format read back as its geometry; and
// `pdmesh mesh MESH`, `pdmesh smooth MESH` and a [[boundary_layer]] on a file's name end to end.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "core/errors.hpp"
#include "geometry/geometry_files.hpp"
#include "io/mesh_formats.hpp"
#include "io/mesh_geometry.hpp"
#include "layers/boundary_layers.hpp"
#include "mesh_measures.hpp"
#include "run_pdmesh.hpp"
#include "temp_files.hpp"

using namespace pdmesh;
namespace fs = std::filesystem;
using Catch::Matchers::Contains;
using pdmesh_test::run_pdmesh;

namespace {

const std::string kData = std::string(PDMESH_SOURCE_DIR) + "/tests/data/mesh_geometry/";

// nx x ny unit squares, two counter-clockwise triangles each, leaving out the squares `skip` names
// (i + nx j); point (i, j) is i + (nx + 1) j. Every edge of one triangle is a boundary edge named
// by name_of(a, b) (an index into `names`, -1: unnamed).
template <class NameOf>
Mesh grid_mesh(int nx, int ny, const std::set<int>& skip, const std::vector<std::string>& names, NameOf name_of) {
  Mesh m;
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i <= nx; ++i) m.points.push_back({double(i), double(j)});
  const auto p = [nx](int i, int j) { return i + (nx + 1) * j; };
  std::map<std::pair<int, int>, int> count;
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      if (skip.count(i + nx * j) != 0) continue;
      m.triangles.push_back({p(i, j), p(i + 1, j), p(i + 1, j + 1)});
      m.triangles.push_back({p(i, j), p(i + 1, j + 1), p(i, j + 1)});
    }
  for (const auto& t : m.triangles)
    for (int k = 0; k < 3; ++k) ++count[std::minmax(t[k], t[(k + 1) % 3])];
  m.curve_names = names;
  for (const auto& [edge, n] : count) {
    if (n != 1) continue;
    const int c = name_of(m.points[edge.first], m.points[edge.second]);
    if (c >= 0) m.boundary_edges.push_back({edge.first, edge.second, c});
  }
  return m;
}

std::set<std::string> names_of(const std::vector<RawCurve>& curves, bool constraint) {
  std::set<std::string> out;
  for (const RawCurve& c : curves)
    if (c.constraint == constraint) out.insert(c.name);
  return out;
}

Geometry built(RawGeometry raw) {
  std::vector<CurveGroup> groups = raw.groups;
  Geometry g = build_geometry(std::move(raw));
  g.groups = std::move(groups);
  return g;
}

Geometry read_as_geometry(const std::string& path) {
  return read_geometry({path}, {}, {}, {ProjectionKind::None, nullptr, {}, mesh_geometry_files()});
}

std::set<double> attributes(const Mesh& m) { return {m.region.begin(), m.region.end()}; }

}  // namespace

TEST_CASE("a mesh with a hole: two loops named by the file, an unnamed loop named boundary0, its area") {
  // 3 x 3 squares without the middle one; the outer edges named "outer", the hole's unnamed.
  const Mesh m = grid_mesh(3, 3, {4}, {"outer"}, [](Vec2 a, Vec2 b) {
    const auto on_rim = [](Vec2 p) { return p.x == 0 || p.x == 3 || p.y == 0 || p.y == 3; };
    return on_rim(a) && on_rim(b) ? 0 : -1;
  });
  const RawGeometry raw = mesh_as_geometry(m, {}, "grid.msh");
  CHECK(names_of(raw.curves, false) == std::set<std::string>{"outer", "boundary0"});
  CHECK(names_of(raw.curves, true).empty());
  const Geometry g = built(raw);
  CHECK(g.loops.size() == 2);
  CHECK(g.area == Approx(8.0).epsilon(1e-14));
  // The square corners are critical points (turning angle); the loops are closed curves.
  CHECK(g.critical.size() == 8);
}

TEST_CASE("a name on separate stretches: NAME, NAME_2 and a group that selects both") {
  const Mesh m = grid_mesh(2, 1, {}, {"wall", "side"}, [](Vec2 a, Vec2 b) { return a.y == b.y ? 0 : 1; });
  const RawGeometry raw = mesh_as_geometry(m, {}, "channel.su2");
  CHECK(names_of(raw.curves, false) == std::set<std::string>{"wall", "wall_2", "side", "side_2"});
  REQUIRE(raw.groups.size() == 2);
  const Geometry g = built(raw);
  const std::vector<int> walls = curves_by_name(g, {"wall"}, "test");
  REQUIRE(walls.size() == 2);
  for (const int c : walls)
    CHECK(g.curves[static_cast<std::size_t>(c)].points.front().y == g.curves[c].points.back().y);
  CHECK(curves_by_name(g, {"wall_2"}, "test").size() == 1);
  CHECK_THROWS_WITH(curves_by_name(g, {"walls"}, "test"), Contains("unknown curve 'walls'"));
  bool noted = false;
  for (const std::string& n : raw.notes) noted = noted || n.find("'wall' names 2 separate curves") != std::string::npos;
  CHECK(noted);
}

TEST_CASE("edges between two regions become a constraint and each part a region seed") {
  Mesh m = grid_mesh(2, 2, {}, {"rim"}, [](Vec2, Vec2) { return 0; });
  for (const auto& t : m.triangles) {
    const double x = (m.points[t[0]].x + m.points[t[1]].x + m.points[t[2]].x) / 3.0;
    m.region.push_back(x < 1.0 ? 1.0 : 2.0);
  }
  const RawGeometry raw = mesh_as_geometry(m, {}, "two.vtu");
  REQUIRE(names_of(raw.curves, true) == std::set<std::string>{"interface0"});
  for (const RawCurve& c : raw.curves)
    if (c.constraint) CHECK(c.points.size() == 3);
  REQUIRE(raw.regions.size() == 2);
  std::set<double> seen;
  for (const GeometryRegion& r : raw.regions) {
    seen.insert(r.attribute);
    CHECK((r.p.x < 1.0) == (r.attribute == 1.0));
  }
  CHECK(seen == std::set<double>{1.0, 2.0});
  const Geometry g = built(raw);
  CHECK(g.area == Approx(4.0).epsilon(1e-14));
  // A named edge between two cells of one region is a constraint with its name.
  Mesh named = grid_mesh(2, 1, {}, {"rim", "cut"}, [](Vec2, Vec2) { return 0; });
  named.boundary_edges.push_back({1, 4, 1});
  CHECK(names_of(mesh_as_geometry(named, {}, "cut.msh").curves, true) == std::set<std::string>{"cut"});
}

TEST_CASE("quads are cells, and Medit corners inside a curve become points") {
  Mesh m;
  m.points = {{0, 0}, {1, 0}, {2, 0}, {2, 1}, {1, 1}, {0, 1}};
  const std::vector<std::array<int, 4>> quads{{0, 1, 4, 5}, {1, 2, 3, 4}};
  m.kind.assign(m.points.size(), NodeKind::Boundary);
  m.kind[1] = NodeKind::Fixed;  // straight through: no critical point without the file's corner
  const RawGeometry raw = mesh_as_geometry(m, quads, "quads.mesh");
  REQUIRE(raw.curves.size() == 1);
  CHECK(raw.curves[0].name == "boundary0");
  REQUIRE(raw.points.size() == 1);
  CHECK(raw.points[0].p == Vec2{1, 0});
  const Geometry g = built(raw);
  CHECK(g.area == Approx(2.0).epsilon(1e-14));
  CHECK(std::any_of(g.critical.begin(), g.critical.end(), [](const CriticalPoint& c) { return c.p == Vec2{1, 0}; }));
}

TEST_CASE("refusals: no cells, a pinched boundary, an edge of three cells, a zero-area quad") {
  Mesh empty;
  CHECK_THROWS_WITH(mesh_as_geometry(empty, {}, "e.msh"), Contains("e.msh: the mesh has no triangles or quadrangles"));
  Mesh pinched;
  pinched.points = {{0, 0}, {1, 0}, {1, 1}, {2, 1}, {2, 2}, {0, 1}};
  pinched.triangles = {{0, 1, 2}, {2, 3, 4}};
  CHECK_THROWS_WITH(mesh_as_geometry(pinched, {}, "p.msh"), Contains("p.msh: the boundary pinches at point 2 (1, 1)"));
  Mesh fin;
  fin.points = {{0, 0}, {1, 0}, {0, 1}, {1, 1}, {0.5, -1}};
  fin.triangles = {{0, 1, 2}, {1, 3, 2}, {0, 4, 1}, {0, 1, 3}};
  CHECK_THROWS_WITH(mesh_as_geometry(fin, {}, "f.msh"), Contains("is a side of 3 cells"));
  Mesh flat;
  flat.points = {{0, 0}, {1, 0}, {2, 0}, {3, 0}};
  CHECK_THROWS_WITH(mesh_as_geometry(flat, {{0, 1, 2, 3}}, "q.mesh"), Contains("q.mesh: quadrangle 0"));
  Mesh degenerate;
  degenerate.points = {{0, 0}, {1, 0}, {2, 0}};
  degenerate.triangles = {{0, 1, 2}};
  CHECK_THROWS_WITH(check_mesh_triangles(degenerate, {}, "d.msh"), Contains("d.msh: triangle 0"));
}

TEST_CASE("a mesh file off the plane z = 0 is refused as a geometry, naming the node") {
  const fs::path dir = pdmesh_test::fresh_dir("mesh_geometry_3d");
  std::ofstream(dir / "tilted.msh") << "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n3\n1 0 0 0\n2 1 0 0\n"
                                       "3 0 1 0.25\n$EndNodes\n$Elements\n1\n1 2 2 0 1 1 2 3\n$EndElements\n";
  CHECK_THROWS_WITH(read_mesh_geometry((dir / "tilted.msh").string()),
                    Contains("must lie in the plane z = 0") && Contains("tilted.msh:8: node 3 has z = 0.25"));
  // The same mesh in the plane reads.
  std::ofstream(dir / "flat.msh") << "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n3\n1 0 0 0\n2 1 0 0\n"
                                     "3 0 1 0\n$EndNodes\n$Elements\n1\n1 2 2 0 1 1 2 3\n$EndElements\n";
  CHECK(read_mesh_geometry((dir / "flat.msh").string()).curves.size() == 1);
}

TEST_CASE("a run's mesh files in every format read back as its geometry") {
  const fs::path out = pdmesh_test::fresh_path("mesh_geometry_formats");
  const auto run = run_pdmesh("mesh '" + kData + "hole_two_regions.toml' --out '" + out.string() + "' -q");
  REQUIRE(run.status == 0);
  const std::set<std::string> boundary{"outer_left", "outer_right", "hole"};
  for (const std::string file : {"mesh.msh", "mesh.vtu", "mesh.su2", "mesh.mesh", "mesh.ele"}) {
    INFO(file);
    const Geometry g = read_as_geometry((out / file).string());
    CHECK(g.loops.size() == 2);
    CHECK(g.area == Approx(15.0).epsilon(1e-12));
    std::set<std::string> walls, constraints;
    for (const Curve& c : g.curves) (c.constraint ? constraints : walls).insert(c.name);
    CHECK(walls == boundary);
    CHECK(constraints == std::set<std::string>{"middle"});
    // SU2 has no volume markers: the regions come back from the other four.
    std::set<double> seeded;
    for (const GeometryRegion& r : g.regions) seeded.insert(r.attribute);
    CHECK(seeded == (file == "mesh.su2" ? std::set<double>{} : std::set<double>{1.0, 2.0}));
  }
}

TEST_CASE("pdmesh mesh MESH re-meshes the domain: area, names, regions and the interface kept") {
  const fs::path first = pdmesh_test::fresh_path("mesh_geometry_first");
  REQUIRE(run_pdmesh("mesh '" + kData + "hole_two_regions.toml' --out '" + first.string() + "' -q").status == 0);
  const fs::path again = pdmesh_test::fresh_path("mesh_geometry_again");
  const auto run = run_pdmesh("mesh '" + (first / "mesh.msh").string() + "' --out '" + again.string() + "' --check -q");
  REQUIRE(run.status == 0);
  const Mesh before = read_mesh(first / "mesh.msh");
  const Mesh after = read_mesh(again / "mesh.msh");
  CHECK(pdmesh_test::mesh_area(after) == Approx(pdmesh_test::mesh_area(before)).epsilon(1e-12));
  CHECK(pdmesh_test::mesh_area(after) == Approx(15.0).epsilon(1e-12));
  CHECK(std::set<std::string>(after.curve_names.begin(), after.curve_names.end()) ==
        std::set<std::string>(before.curve_names.begin(), before.curve_names.end()));
  CHECK(attributes(after) == std::set<double>{1.0, 2.0});
  // Every triangle keeps its side of the interface x = 3.
  for (std::size_t t = 0; t < after.triangles.size(); ++t) {
    const auto& v = after.triangles[t];
    const double x = (after.points[v[0]].x + after.points[v[1]].x + after.points[v[2]].x) / 3.0;
    CHECK(after.region[t] == (x < 3.0 ? 1.0 : 2.0));
  }
}

TEST_CASE("pdmesh smooth MESH without --geometry uses the mesh's own domain") {
  const fs::path first = pdmesh_test::fresh_path("mesh_geometry_smooth_in");
  REQUIRE(run_pdmesh("mesh '" + kData + "hole_two_regions.toml' --out '" + first.string() + "' -q").status == 0);
  const fs::path out = pdmesh_test::fresh_path("mesh_geometry_smooth");
  const auto run = run_pdmesh("smooth '" + (first / "mesh.vtu").string() + "' --out '" + out.string() + "' -q");
  INFO(run.output);
  REQUIRE(run.status == 0);
  const Mesh after = read_mesh(out / "mesh.msh");
  CHECK(pdmesh_test::mesh_area(after) == Approx(15.0).epsilon(1e-12));
  CHECK(attributes(after) == std::set<double>{1.0, 2.0});
}

TEST_CASE("a [[boundary_layer]] on a name the file gives to two holes grows on both") {
  const fs::path first = pdmesh_test::fresh_path("mesh_geometry_holes");
  REQUIRE(run_pdmesh("mesh '" + kData + "two_holes.poly' --size 0.4 --out '" + first.string() + "' -q").status == 0);
  // The two holes' curves both named "wall" in an SU2 file, as a marker on several bodies is.
  Mesh m = read_mesh(first / "mesh.msh");
  m.curve_groups.clear();  // the file's groups name the curves as they were
  for (std::string& name : m.curve_names)
    if (name != "curve0") name = "wall";
  const fs::path dir = pdmesh_test::fresh_dir("mesh_geometry_layer_case");
  write_mesh(m, dir, "holes", {"su2"});
  std::ofstream(dir / "case.toml") << "preset = \"best\"\n[geometry]\nfiles = [\"holes.su2\"]\n[spacing]\nsize = 0.4\n"
                                      "[simulation]\ndevice = \"host\"\n[[boundary_layer]]\ncurves = [\"wall\"]\n"
                                      "first_height = 0.02\ngrowth = 1.2\nthickness = 0.1\nelements = \"quads\"\n";
  const fs::path out = pdmesh_test::fresh_path("mesh_geometry_layer");
  const auto run = run_pdmesh("mesh '" + (dir / "case.toml").string() + "' --out '" + out.string() + "' -q");
  INFO(run.output);
  REQUIRE(run.status == 0);
  CHECK_THAT(run.output, Contains("'wall' names 2 separate curves: wall, wall_2"));
  MeshReadReport report;
  SurfaceCells cells;
  cells.region = "boundary_layer";
  const Mesh merged = read_mesh(out / "mesh.msh", report, &cells);
  REQUIRE(cells.region_found);
  // Layer quads around each hole: centres within the layer's thickness of the holes' squares.
  int left = 0, right = 0;
  for (std::size_t q = 0; q < cells.quads.size(); ++q) {
    if (!cells.quad_in_region[q]) continue;
    Vec2 c{0, 0};
    for (const int v : cells.quads[q]) c = c + merged.points[static_cast<std::size_t>(v)] * 0.25;
    (c.x < 3.0 ? left : right) += 1;
    CHECK(((c.x > 0.85 && c.x < 2.15) || (c.x > 3.85 && c.x < 5.15)));
    CHECK((c.y > 0.85 && c.y < 2.15));
  }
  CHECK(left > 0);
  CHECK(right > 0);
}

TEST_CASE("pdmesh mesh refuses a pinched mesh file, naming the file and the point, and writes nothing") {
  Mesh pinched;
  pinched.points = {{0, 0}, {1, 0}, {1, 1}, {2, 1}, {2, 2}, {0, 1}};
  pinched.triangles = {{0, 1, 2}, {2, 3, 4}};
  const fs::path dir = pdmesh_test::fresh_dir("mesh_geometry_pinched");
  write_mesh(pinched, dir, "pinched", {"msh"});
  const fs::path out = pdmesh_test::fresh_path("mesh_geometry_pinched_out");
  const auto run = run_pdmesh("mesh '" + (dir / "pinched.msh").string() + "' --out '" + out.string() + "'");
  CHECK(run.status == 2);
  CHECK_THAT(run.output, Contains("pinched.msh: the boundary pinches at point 2 (1, 1)"));
  CHECK(!fs::exists(out));
}
