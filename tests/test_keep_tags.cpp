// A mesh file's physical groups kept through a re-mesh: the two-material Gmsh file of
// tests/data/keep_tags (walls: dimension-1 tag 5 over all seven curves, steel 11, copper 22) through
// `pdmesh mesh` into MSH 4.1 and 2.2, SU2 and Medit, read back with the same tags; the writers' tag
// rules (curve_tags, region_surfaces) on meshes built here, a curve file's run numbered as before.
#include <catch2/catch.hpp>

#include <filesystem>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "io/mesh_formats.hpp"
#include "io/mesh_geometry.hpp"
#include "io/mesh_io_common.hpp"
#include "io/msh_writer.hpp"
#include "msh_physical_names.hpp"
#include "run_pdmesh.hpp"
#include "temp_files.hpp"

using namespace pdmesh;
namespace fs = std::filesystem;
using pdmesh_test::physical_names;
using pdmesh_test::run_pdmesh;

namespace {

const std::string kData = std::string(PDMESH_SOURCE_DIR) + "/tests/data/";

// The two-material file re-meshed into `formats` (once per process and format list).
fs::path remeshed(const std::string& formats) {
  const fs::path out = pdmesh_test::fresh_path("keep_tags_" + formats.substr(0, formats.find(',')));
  const auto run = run_pdmesh("mesh '" + kData + "keep_tags/two_materials.msh' --out '" + out.string() +
                              "' --formats " + formats + " --device host -q");
  INFO(run.output);
  REQUIRE(run.status == 0);
  return out;
}

// The input's groups read back: one curve "walls" with tag 5 over the edges of the outer boundary
// (x = 0, x = 2, y = 0, y = 1) and of the interface x = 1; regions 11 (x < 1) and 22 named.
void check_read_back(const Mesh& m) {
  REQUIRE(m.curve_names == std::vector<std::string>{"walls"});
  REQUIRE(m.curve_groups.size() == 1);
  CHECK(m.curve_groups[0].tag == 5);
  CHECK(m.curve_groups[0].name == "walls");
  CHECK(m.curve_groups[0].curves == std::vector<int>{0});
  std::size_t outer = 0, interface = 0;
  for (const BoundaryEdge& e : m.boundary_edges) {
    const Vec2 a = m.points[static_cast<std::size_t>(e.a)], b = m.points[static_cast<std::size_t>(e.b)];
    if (a.x == 1.0 && b.x == 1.0)
      ++interface;
    else if ((a.x == b.x && (a.x == 0.0 || a.x == 2.0)) || (a.y == b.y && (a.y == 0.0 || a.y == 1.0)))
      ++outer;
    CHECK(e.curve == 0);
  }
  CHECK(interface >= 2);
  CHECK(outer >= 6);
  CHECK(interface + outer == m.boundary_edges.size());
  REQUIRE(m.region.size() == m.triangles.size());
  for (std::size_t t = 0; t < m.triangles.size(); ++t) {
    const auto& v = m.triangles[t];
    const double x = (m.points[v[0]].x + m.points[v[1]].x + m.points[v[2]].x) / 3.0;
    CHECK(m.region[t] == (x < 1.0 ? 11.0 : 22.0));
  }
  CHECK(region_label(m, 11.0) == "steel");
  CHECK(region_label(m, 22.0) == "copper");
}

}  // namespace

TEST_CASE("a re-meshed Gmsh file keeps its physical tags and names in MSH 4.1 and reads back the same") {
  const fs::path out = remeshed("msh,su2,mesh,vtu");
  const std::string msh = pdmesh_test::slurp(out / "mesh.msh");
  CHECK(physical_names(msh) == std::vector<std::string>{"3", "1 5 \"walls\"", "2 11 \"steel\"", "2 22 \"copper\""});
  const Mesh back = read_mesh(out / "mesh.msh");
  check_read_back(back);
  // Again through pdmesh: the output as the geometry gives the same groups.
  const fs::path again = pdmesh_test::fresh_path("keep_tags_again");
  REQUIRE(run_pdmesh("mesh '" + (out / "mesh.msh").string() + "' --out '" + again.string() +
                     "' --formats msh --device host -q")
              .status == 0);
  CHECK(physical_names(pdmesh_test::slurp(again / "mesh.msh")) == physical_names(msh));
  check_read_back(read_mesh(again / "mesh.msh"));

  SECTION("SU2: one marker 'walls' with every boundary and interface edge") {
    const std::string su2 = pdmesh_test::slurp(out / "mesh.su2");
    CHECK(su2.find("NMARK= 1\nMARKER_TAG= walls\nMARKER_ELEMS= " + std::to_string(back.boundary_edges.size()) + "\n") !=
          std::string::npos);
  }
  SECTION("VTU: the curves' group tag and name as field data, read back as the group") {
    const Mesh m = read_mesh(out / "mesh.vtu");
    CHECK(m.curve_names == std::vector<std::string>{"walls", "walls_2"});
    REQUIRE(m.curve_groups.size() == 1);
    CHECK(m.curve_groups[0].tag == 5);
    CHECK(m.curve_groups[0].name == "walls");
    CHECK(m.curve_groups[0].curves == std::vector<int>{0, 1});
    CHECK(std::set<double>(m.region.begin(), m.region.end()) == std::set<double>{11.0, 22.0});
    // Written again as MSH: one group 5 over both curves.
    CHECK(physical_names(msh41_string(m)) == physical_names(msh));
  }
  SECTION("Medit: edge references 5, triangle references 11 and 22, read back as the regions") {
    const std::string medit = pdmesh_test::slurp(out / "mesh.mesh");
    CHECK(medit.find("# ref 5: curve walls\n# ref 11: region steel\n# ref 22: region copper\n") != std::string::npos);
    const Mesh m = read_mesh(out / "mesh.mesh");
    CHECK(m.curve_names == std::vector<std::string>{"walls"});
    REQUIRE(m.region.size() == m.triangles.size());
    CHECK(std::set<double>(m.region.begin(), m.region.end()) == std::set<double>{11.0, 22.0});
  }
}

TEST_CASE("the file as the geometry: one group 'walls' with tag 5 over its boundary and interface curves") {
  const RawGeometry raw = read_mesh_geometry(kData + "keep_tags/two_materials.msh");
  REQUIRE(raw.groups.size() == 1);
  CHECK(raw.groups[0].name == "walls");
  CHECK(raw.groups[0].tag == 5);
  CHECK(raw.groups[0].curves == std::vector<std::string>{"walls", "walls_2"});
  REQUIRE(raw.notes.size() == 1);
  CHECK(raw.notes[0].find("the physical group 'walls' (tag 5) is on 2 separate curves: walls, walls_2") !=
        std::string::npos);
  CHECK(raw.notes[0].find("as one group 'walls' with tag 5") != std::string::npos);
  std::set<double> attributes;
  for (const GeometryRegion& r : raw.regions) attributes.insert(r.attribute);
  CHECK(attributes == std::set<double>{11.0, 22.0});
}

TEST_CASE("a re-meshed Gmsh file keeps its physical tags and names in MSH 2.2") {
  const fs::path out = remeshed("msh22");
  const std::string msh = pdmesh_test::slurp(out / "mesh.msh");
  REQUIRE(msh.rfind("$MeshFormat\n2.2 ", 0) == 0);
  CHECK(physical_names(msh) == std::vector<std::string>{"3", "1 5 \"walls\"", "2 11 \"steel\"", "2 22 \"copper\""});
  check_read_back(read_mesh(out / "mesh.msh"));
}

TEST_CASE("a curve file's run numbers its curves 1, 2, ... and the domain after them, as before") {
  const fs::path out = pdmesh_test::fresh_path("keep_tags_crv");
  const auto run = run_pdmesh("mesh '" + kData + "interop/rectangle.crv' --size 0.5 --out '" + out.string() +
                              "' --formats msh --device host -q");
  INFO(run.output);
  REQUIRE(run.status == 0);
  const std::vector<std::string> names = physical_names(pdmesh_test::slurp(out / "mesh.msh"));
  const Mesh m = read_mesh(out / "mesh.msh");
  REQUIRE(names.size() == m.curve_names.size() + 2);
  for (std::size_t c = 0; c < m.curve_names.size(); ++c)
    CHECK(names[c + 1] == "1 " + std::to_string(c + 1) + " \"" + m.curve_names[c] + "\"");
  CHECK(names.back() == "2 " + std::to_string(m.curve_names.size() + 1) + " \"domain\"");
}

TEST_CASE("curve_tags: groups keep their tags, the other curves take the free numbers in curve order") {
  Mesh m;
  m.curve_names = {"a", "b", "c", "d"};
  CurveTags plain = curve_tags(m);
  CHECK(plain.of_curve == std::vector<long long>{1, 2, 3, 4});
  REQUIRE(plain.groups.size() == 4);
  CHECK(plain.groups[2].name == "c");
  m.curve_groups = {{2, "wall", {0, 3}}, {7, "inlet", {2}}};
  const CurveTags t = curve_tags(m);
  CHECK(t.of_curve == std::vector<long long>{2, 1, 7, 2});
  REQUIRE(t.groups.size() == 3);
  CHECK(t.groups[0].tag == 1);
  CHECK(t.groups[0].name == "b");
  CHECK(t.groups[1].tag == 2);
  CHECK(t.groups[1].name == "wall");
  CHECK(t.groups[1].curves == std::vector<int>{0, 3});
  CHECK(t.group_of_tag(7) == 2);
}

TEST_CASE("region_surfaces: a positive whole attribute is its own tag, the others numbered from `first`") {
  Mesh m;
  m.points = {{0, 0}, {1, 0}, {0, 1}, {1, 1}};
  m.triangles = {{0, 1, 2}, {1, 3, 2}, {0, 1, 3}, {0, 3, 2}};
  m.region = {0.0, 2.5, 5.0, 6.0};
  // Sorted: 0 (j 0), 2.5 (j 1), 5, 6. From first = 5: 0 -> 5 is taken by 5, so 7; 2.5 -> 6 taken, 8.
  const RegionSurfaces s = region_surfaces(m, 5);
  CHECK(s.names == std::vector<std::string>{"region_0", "region_2.5", "region_5", "region_6"});
  CHECK(s.tags == std::vector<long long>{7, 8, 5, 6});
  m.region.clear();
  const RegionSurfaces domain = region_surfaces(m, 5);
  CHECK(domain.tags == std::vector<long long>{5});
}
