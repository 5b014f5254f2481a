// Names of regional attributes (Mesh::region_names): a Gmsh file's named physical surfaces and Medit
// reference comments read as names, the VTU field data round trip, the case's geometry.region_names
// written into every mesh file that can carry them, the names kept when a named mesh file is the
// geometry of a run, and geometry.region_names' refusals.
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <string>

#include "io/mesh_formats.hpp"
#include "io/msh_reader.hpp"
#include "io/vtu_reader.hpp"
#include "io/vtu_writer.hpp"
#include "run_pdmesh.hpp"
#include "temp_files.hpp"

using namespace pdmesh;
namespace fs = std::filesystem;
using Catch::Matchers::Contains;
using pdmesh_test::run_pdmesh;

namespace {

const std::string kData = std::string(PDMESH_SOURCE_DIR) + "/tests/data/mesh_geometry/";

std::map<double, std::string> names_of(const Mesh& m) {
  std::map<double, std::string> out;
  for (const RegionName& r : m.region_names) out[r.attribute] = r.name;
  return out;
}

// Two unit squares side by side, x in [0, 2]: the left one's triangles in physical surface
// `left_tag`, the right one's in `right_tag`, the outline in the line group 1 "wall"; MSH 2.2 as Gmsh
// writes it, with the 2-D names given by `surface_names` ("TAG \"NAME\"" lines).
std::string two_squares_msh(int left_tag, int right_tag, const std::map<int, std::string>& surface_names) {
  std::string s = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$PhysicalNames\n" + std::to_string(1 + surface_names.size()) +
                  "\n1 1 \"wall\"\n";
  for (const auto& [tag, name] : surface_names) s += "2 " + std::to_string(tag) + " \"" + name + "\"\n";
  s += "$EndPhysicalNames\n$Nodes\n6\n1 0 0 0\n2 1 0 0\n3 2 0 0\n4 0 1 0\n5 1 1 0\n6 2 1 0\n$EndNodes\n";
  s += "$Elements\n10\n";
  const char* lines[] = {"1 2", "2 3", "3 6", "6 5", "5 4", "4 1"};
  int e = 1;
  for (const char* l : lines) s += std::to_string(e++) + " 1 2 1 1 " + l + "\n";
  const auto tri = [&](int tag, const char* nodes) {
    s += std::to_string(e++) + " 2 2 " + std::to_string(tag) + " " + std::to_string(tag) + " " + nodes + "\n";
  };
  tri(left_tag, "1 2 5");
  tri(left_tag, "1 5 4");
  tri(right_tag, "2 3 6");
  tri(right_tag, "2 6 5");
  s += "$EndElements\n";
  return s;
}

Mesh parsed(const std::string& text) {
  MeshReadReport report;
  return parse_msh("gmsh.msh", text, report);
}

void write_text(const fs::path& p, const std::string& text) { std::ofstream(p, std::ios::binary) << text; }

}  // namespace

TEST_CASE("a Gmsh file's named physical surfaces are regions with their names") {
  const Mesh m = parsed(two_squares_msh(7, 9, {{7, "fluid"}, {9, "solid"}}));
  CHECK(m.region == std::vector<double>{7, 7, 9, 9});
  CHECK(names_of(m) == std::map<double, std::string>{{7, "fluid"}, {9, "solid"}});
  // One surface with a name is one region, so that its name is kept; without a name, or named
  // "domain" (pdmesh's own file without regions), it is none.
  const Mesh one = parsed(two_squares_msh(7, 7, {{7, "fluid"}}));
  CHECK(one.region == std::vector<double>{7, 7, 7, 7});
  CHECK(names_of(one) == std::map<double, std::string>{{7, "fluid"}});
  CHECK(parsed(two_squares_msh(7, 7, {})).region.empty());
  CHECK(parsed(two_squares_msh(7, 7, {{7, "domain"}})).region.empty());
  // Unnamed groups are regions by tag, without names; "region_<a>" gives the attribute a.
  const Mesh tags = parsed(two_squares_msh(7, 9, {}));
  CHECK(tags.region == std::vector<double>{7, 7, 9, 9});
  CHECK(tags.region_names.empty());
  const Mesh ours = parsed(two_squares_msh(7, 9, {{7, "region_1.5"}, {9, "solid"}}));
  CHECK(ours.region == std::vector<double>{1.5, 1.5, 9, 9});
  CHECK(names_of(ours) == std::map<double, std::string>{{9, "solid"}});
}

TEST_CASE("region names survive MSH, VTU and Medit files") {
  Mesh m = parsed(two_squares_msh(7, 9, {{7, "fluid"}, {9, "solid"}}));
  const fs::path dir = pdmesh_test::fresh_dir("region_names_formats");
  write_mesh(m, dir, "m", {"msh", "vtu", "mesh"});
  for (const char* ext : {".msh", ".vtu", ".mesh"}) {
    INFO(ext);
    const Mesh back = read_mesh(dir / (std::string("m") + ext));
    REQUIRE(back.region.size() == 4);
    REQUIRE(back.region_names.size() == 2);
    // The left squares keep one name, the right ones the other.
    const auto names = names_of(back);
    CHECK(names.at(back.region[0]) == "fluid");
    CHECK(names.at(back.region[1]) == "fluid");
    CHECK(names.at(back.region[2]) == "solid");
    CHECK(names.at(back.region[3]) == "solid");
  }
  // The VTU file keeps the attributes as well; MSH and Medit name the writer's tags.
  CHECK(names_of(read_mesh(dir / "m.vtu")) == names_of(m));
  CHECK(read_mesh(dir / "m.vtu").region == m.region);
  CHECK_THAT(pdmesh_test::slurp(dir / "m.msh"), Contains("\"fluid\"") && Contains("\"solid\""));
  CHECK_THAT(pdmesh_test::slurp(dir / "m.mesh"), Contains("region fluid") && Contains("region solid"));
  // A name with a double quote is written with '_' (MSH quotes names).
  m.region_names[0].name = "a\"b";
  write_mesh(m, dir, "q", {"msh"});
  CHECK(names_of(read_mesh(dir / "q.msh")).begin()->second == "a_b");
}

TEST_CASE("a VTU file's region names must match their attributes") {
  const Mesh m = parsed(two_squares_msh(7, 9, {{7, "fluid"}, {9, "solid"}}));
  std::string text = vtu_string(m, VtuFormat::Ascii);
  MeshReadReport report;
  CHECK(names_of(parse_vtu("m.vtu", text, report)) == names_of(m));
  // One attribute for two names.
  const std::string tag = "Name=\"region_name_attributes\" NumberOfTuples=\"2\"";
  const auto at = text.find(tag);
  REQUIRE(at != std::string::npos);
  text.replace(at, tag.size(), "Name=\"region_name_attributes\" NumberOfTuples=\"1\"");
  const auto open_end = text.find('>', at) + 1;
  text.replace(open_end, text.find("</DataArray>", at) - open_end, "\n7\n");
  CHECK_THROWS_WITH(parse_vtu("bad.vtu", text, report),
                    Contains("bad.vtu") && Contains("region_names holds 2 names for 1 attributes"));
  // Attributes out of order.
  std::string swapped = vtu_string(m, VtuFormat::Ascii);
  const auto a = swapped.find("Name=\"region_name_attributes\"");
  const auto b = swapped.find('>', a) + 1;
  swapped.replace(b, swapped.find("</DataArray>", a) - b, "\n9 7\n");
  CHECK_THROWS_WITH(parse_vtu("swapped.vtu", swapped, report), Contains("not ascending: 7 after 9"));
}

TEST_CASE("geometry.region_names names a .poly's regions in the mesh files") {
  const fs::path dir = pdmesh_test::fresh_dir("region_names_case");
  std::string toml = pdmesh_test::slurp(kData + "hole_two_regions.toml");
  toml.replace(toml.find("files = [\"hole_two_regions.poly\"]"),
               std::string("files = [\"hole_two_regions.poly\"]").size(),
               "files = [\"" + kData + "hole_two_regions.poly\"]\nregion_names = { 1 = \"steel\", 2 = \"copper\" }");
  write_text(dir / "case.toml", toml);
  const fs::path out = dir / "out";
  const auto run = run_pdmesh("mesh '" + (dir / "case.toml").string() + "' --out '" + out.string() + "' -q");
  REQUIRE(run.status == 0);
  // The VTU and .ele files keep the attributes; the VTU and Medit files the names too.
  const Mesh vtu = read_mesh(out / "mesh.vtu");
  CHECK(names_of(vtu) == std::map<double, std::string>{{1, "steel"}, {2, "copper"}});
  CHECK(names_of(read_mesh(out / "mesh.mesh")) == std::map<double, std::string>{{1, "steel"}, {2, "copper"}});
  const Mesh msh = read_mesh(out / "mesh.msh");
  std::set<std::string> msh_names;
  for (const RegionName& r : msh.region_names) msh_names.insert(r.name);
  CHECK(msh_names == std::set<std::string>{"steel", "copper"});
  CHECK(read_mesh(out / "mesh.ele").region == vtu.region);
  // A re-mesh of the written mesh keeps the names on the same sides of the interface.
  const fs::path again = dir / "again";
  REQUIRE(run_pdmesh("mesh '" + (out / "mesh.msh").string() + "' --out '" + again.string() + "' -q").status == 0);
  const Mesh after = read_mesh(again / "mesh.vtu");
  const auto names = names_of(after);
  REQUIRE(after.region.size() == after.triangles.size());
  for (std::size_t t = 0; t < after.triangles.size(); ++t) {
    const auto& v = after.triangles[t];
    const double x = (after.points[v[0]].x + after.points[v[1]].x + after.points[v[2]].x) / 3.0;
    CHECK(names.at(after.region[t]) == (x < 3.0 ? "steel" : "copper"));
  }
}

TEST_CASE("geometry.region_names refuses an attribute without a region and names that are not plain") {
  const fs::path dir = pdmesh_test::fresh_dir("region_names_refused");
  const std::string base = pdmesh_test::slurp(kData + "hole_two_regions.toml");
  const auto refused = [&](const std::string& names, const std::string& message) {
    INFO(names);
    std::string toml = base;
    toml.replace(toml.find("files = [\"hole_two_regions.poly\"]"),
                 std::string("files = [\"hole_two_regions.poly\"]").size(),
                 "files = [\"" + kData + "hole_two_regions.poly\"]\nregion_names = " + names);
    write_text(dir / "case.toml", toml);
    const fs::path out = dir / "out";
    const auto run = run_pdmesh("mesh '" + (dir / "case.toml").string() + "' --out '" + out.string() + "' -q");
    CHECK(run.status == 2);
    CHECK_THAT(run.output, Contains("case.toml:8") && Contains(message));
    CHECK_FALSE(fs::exists(out));
  };
  refused("{ 3 = \"steel\" }", "attribute 3 is no region's of the geometry (its attributes: 1, 2)");
  refused("{ 1 = \"two words\" }", "'two words' is not a plain name");
  refused("{ 1 = \"region_4\" }", "'region_4' is not a plain name");
  refused("{ 0 = \"none\" }", "'0' is not a regional attribute");
  refused("{ x = \"steel\" }", "'x' is not a regional attribute");
  refused("{ 1 = \"steel\", 2 = \"steel\" }", "'steel' names two attributes");
  refused("[1, 2]", "geometry.region_names must be a table");
}
