// Regional attributes on the mesh (mesh/region_tags.cpp), in the mesh files (MSH physical surfaces,
// VTU cell data, Triangle .ele attribute, Medit triangle references) and read back from each, and
// end to end from a .poly file.
#include <algorithm>
#include <array>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>

#include <catch2/catch.hpp>

#include "io/medit_reader.hpp"
#include "io/medit_writer.hpp"
#include "io/mesh_formats.hpp"
#include "io/msh_reader.hpp"
#include "io/msh_writer.hpp"
#include "io/triangle_writer.hpp"
#include "io/vtu_writer.hpp"
#include "mesh/region_tags.hpp"
#include "run_pdmesh.hpp"
#include "temp_files.hpp"

using namespace pdmesh;
using Catch::Matchers::Contains;
namespace fs = std::filesystem;

namespace {

// Two unit squares side by side, two triangles each; the edge 1-4 (x = 1) between them.
Mesh two_squares() {
  Mesh m;
  m.points = {{0, 0}, {1, 0}, {2, 0}, {0, 1}, {1, 1}, {2, 1}};
  m.triangles = {{0, 1, 4}, {0, 4, 3}, {1, 2, 5}, {1, 5, 4}};
  m.curve_names = {"outer"};
  m.boundary_edges = {{0, 1, 0}, {1, 2, 0}, {2, 5, 0}, {5, 4, 0}, {4, 3, 0}, {3, 0, 0}};
  return m;
}

// Each triangle's region by its sorted vertices: MSH 4.1 writes the triangles grouped by region.
std::map<std::array<int, 3>, double> region_of_triangles(const Mesh& m) {
  std::map<std::array<int, 3>, double> out;
  for (std::size_t t = 0; t < m.triangles.size(); ++t) {
    std::array<int, 3> v = m.triangles[t];
    std::sort(v.begin(), v.end());
    out[v] = t < m.region.size() ? m.region[t] : -1.0;
  }
  return out;
}

Geometry segments(const std::vector<std::pair<Vec2, Vec2>>& list) {
  Geometry g;
  for (const auto& [a, b] : list) {
    g.segments.push_back({a, b, 0, static_cast<int>(g.segments.size()), dist(a, b)});
    g.extents.add(a);
    g.extents.add(b);
  }
  return g;
}

std::vector<GeometryRegion> two_regions() {
  GeometryRegion left, right;
  left.p = {0.3, 0.6};
  left.attribute = 1;
  right.p = {1.7, 0.2};
  right.attribute = 2.5;
  return {left, right};
}

}  // namespace

TEST_CASE("region tags: the flood stops at edges on a geometry segment", "[mesh]") {
  const Mesh m = two_squares();
  // The constraint x = 1: the edge 1-4 lies on it.
  const Geometry g = segments({{{1, 0}, {1, 1}}});
  CHECK(region_tags(m, two_regions(), g) == std::vector<double>{1, 1, 2.5, 2.5});
  // Without the segment the regions are one subdomain: the later region fills it all.
  CHECK(region_tags(m, two_regions(), Geometry{}) == std::vector<double>{2.5, 2.5, 2.5, 2.5});
  // A segment that the edge only touches at one end blocks nothing.
  CHECK(region_tags(m, two_regions(), segments({{{1, 1}, {1, 2}}})) == std::vector<double>{2.5, 2.5, 2.5, 2.5});
  // One region on the left only: the right stays 0.
  CHECK(region_tags(m, {two_regions()[0]}, g) == std::vector<double>{1, 1, 0, 0});
  CHECK(region_tags(m, {}, g).empty());
}

TEST_CASE("region tags in the mesh files", "[mesh][io]") {
  Mesh m = two_squares();
  m.region = {1, 1, 2.5, 2.5};
  const std::string msh = msh41_string(m);
  // A whole attribute is its own tag; 2.5 takes the number after the curves and its index (1 + 1 + 1).
  CHECK_THAT(msh, Contains("2 1 \"region_1\"\n2 3 \"region_2.5\"\n"));
  CHECK_THAT(msh, Contains(" 1 1 0\n2 0 0 0 2 1 0 1 3 0\n$EndEntities"));
  CHECK_THAT(msh, Contains("$Entities\n0 1 2 0\n"));
  CHECK_THAT(msh, Contains("2 1 2 2\n7 1 2 5\n8 1 5 4\n"));  // surface 1 holds the left triangles
  CHECK_THAT(msh, Contains("2 2 2 2\n9 2 3 6\n10 2 6 5\n"));
  CHECK_THAT(msh, !Contains("domain"));
  const std::string msh22 = msh22_string(m);
  CHECK_THAT(msh22, Contains("7 2 2 1 1 1 2 5\n"));
  CHECK_THAT(msh22, Contains("9 2 2 3 2 2 3 6\n"));
  CHECK_THAT(vtu_string(m, VtuFormat::Ascii), Contains("Name=\"region\""));
  const TriangleFiles tri = triangle_strings(m);
  CHECK_THAT(tri.ele, Contains("4 3 1\n1 1 2 5 1\n"));
  CHECK_THAT(tri.ele, Contains("3 2 3 6 2.5\n"));
  // Medit: the triangle references are the regions' (1 its own, 2.5 the second in ascending attribute
  // order), named.
  const std::string medit = medit_string(m);
  CHECK_THAT(medit, Contains("# ref 1: region region_1\n# ref 2: region region_2.5\n"));
  CHECK_THAT(medit, Contains("Triangles\n4\n1 2 5 1\n1 5 4 1\n2 3 6 2\n2 6 5 2\n"));
  // Without regions: one "domain" surface, no region array, no attribute.
  m.region.clear();
  CHECK_THAT(msh41_string(m), Contains("2 2 \"domain\"\n") && Contains("$Entities\n0 1 1 0\n"));
  CHECK_THAT(vtu_string(m, VtuFormat::Ascii), !Contains("Name=\"region\""));
  CHECK_THAT(triangle_strings(m).ele, Contains("4 3 0\n1 1 2 5\n"));
  CHECK_THAT(medit_string(m), Contains("Triangles\n4\n1 2 5 0\n") && !Contains("region"));
}

TEST_CASE("region tags read back from every format that writes them", "[mesh][io]") {
  const fs::path dir = pdmesh_test::fresh_dir("region_read_back");
  Mesh m = two_squares();
  m.region = {7, 7, 2.5, 2.5};
  for (const std::string format : {"msh", "msh22", "vtu", "triangle", "mesh"}) {
    INFO(format);
    const auto written = write_mesh(m, dir, format, {format});
    MeshReadReport report;
    const Mesh back = read_mesh(format == "triangle" ? dir / "triangle.ele" : written.front(), report);
    CHECK(back.region.size() == m.region.size());
    CHECK(region_of_triangles(back) == region_of_triangles(m));
    // Written again, the regions carry the same names.
    CHECK(region_surfaces(back, 1).names == std::vector<std::string>{"region_2.5", "region_7"});
  }
  // Without regions nothing is read as one.
  m.region.clear();
  for (const std::string format : {"msh", "vtu", "triangle", "mesh"}) {
    INFO(format);
    const auto written = write_mesh(m, dir, "plain_" + format, {format});
    MeshReadReport report;
    CHECK(read_mesh(format == "triangle" ? dir / "plain_triangle.ele" : written.front(), report).region.empty());
  }
}

TEST_CASE("regions of files pdmesh did not write: Medit references without names, Gmsh's physical surfaces",
          "[mesh][io]") {
  // mmg2d writes the triangle references back without pdmesh's comments: the reference is the
  // attribute, which the writer names region_<N>.
  const std::string medit =
      "MeshVersionFormatted 2\nDimension 2\nVertices\n6\n0 0 1\n1 0 1\n2 0 1\n0 1 1\n1 1 1\n2 1 1\n"
      "Triangles\n4\n1 2 5 3\n1 5 4 3\n2 3 6 0\n2 6 5 0\nEnd\n";
  MeshReadReport report;
  const Mesh mm = parse_medit_mesh("mmg.mesh", medit, report);
  CHECK(mm.region == std::vector<double>{3, 3, 0, 0});
  CHECK(region_surfaces(mm, 1).names == std::vector<std::string>{"region_0", "region_3"});
  // A layered run's file names the layer's reference boundary_layer (its cells are SurfaceCells'): the
  // other references decide whether there are regions; where there are, the layer's triangles are one
  // more, attribute its reference, named boundary_layer.
  const std::string body = medit.substr(std::string("MeshVersionFormatted 2\nDimension 2\n").size());
  std::string layered = "MeshVersionFormatted 2\nDimension 2\n# ref 1: region boundary_layer\n" + body;
  layered.replace(layered.find("2 3 6 0\n"), 8, "2 3 6 1\n");
  const Mesh with_layer = parse_medit_mesh("layer.mesh", layered, report);
  CHECK(with_layer.region == std::vector<double>{3, 3, 1, 0});
  CHECK(region_label(with_layer, 1.0) == "boundary_layer");
  // Without regions (the core's references 0, the layer's 1): none.
  std::string plain = "MeshVersionFormatted 2\nDimension 2\n# ref 1: region boundary_layer\n" + body;
  plain.replace(plain.find("1 2 5 3\n1 5 4 3\n"), 16, "1 2 5 1\n1 5 4 1\n");
  CHECK(parse_medit_mesh("layer.mesh", plain, report).region.empty());
  // Gmsh: two named physical surfaces; a group's attribute is its tag (the name is not region_<a>).
  const std::string msh =
      "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$PhysicalNames\n2\n2 5 \"fluid\"\n2 9 \"solid\"\n"
      "$EndPhysicalNames\n$Nodes\n6\n1 0 0 0\n2 1 0 0\n3 2 0 0\n4 0 1 0\n5 1 1 0\n6 2 1 0\n$EndNodes\n"
      "$Elements\n4\n1 2 2 5 1 1 2 5\n2 2 2 5 1 1 5 4\n3 2 2 9 2 2 3 6\n4 2 2 9 2 2 6 5\n$EndElements\n";
  CHECK(parse_msh("g.msh", msh, report).region == std::vector<double>{5, 5, 9, 9});
  // One named Gmsh surface group is one region, so that its name is kept (test_region_names.cpp);
  // without a name it is the whole domain: no regions.
  std::string one = msh;
  one.replace(one.find("2 2 9 2 2 3 6"), 13, "2 2 5 1 2 3 6");
  one.replace(one.find("2 2 9 2 2 6 5"), 13, "2 2 5 1 2 6 5");
  CHECK(parse_msh("one.msh", one, report).region == std::vector<double>{5, 5, 5, 5});
  std::string unnamed = one;
  unnamed.replace(unnamed.find("$PhysicalNames"), unnamed.find("$Nodes") - unnamed.find("$PhysicalNames"), "");
  CHECK(parse_msh("unnamed.msh", unnamed, report).region.empty());
}

TEST_CASE("pdmesh mesh on a .poly with a regional attribute writes its tag", "[cli]") {
  const fs::path dir = pdmesh_test::fresh_dir("region_tags");
  // The unit square, one region with attribute 7 and a maximum area (noted, not applied).
  std::ofstream(dir / "square.poly") << "4 2 0 0\n1 0 0\n2 1 0\n3 1 1\n4 0 1\n4 0\n1 1 2\n2 2 3\n3 3 4\n4 4 1\n0\n"
                                        "1\n1 0.5 0.5 7 0.01\n";
  const fs::path out = dir / "out";
  const auto r = pdmesh_test::run_pdmesh("mesh '" + (dir / "square.poly").string() + "' --out '" + out.string() +
                                         "' --iterations 0 --formats msh,vtu,mesh --quiet");
  CHECK(r.status == 0);
  CHECK_THAT(r.output,
             Contains("pdmesh: note: ") && Contains("square.poly:13: 1 region gives a maximum triangle area"));
  CHECK_THAT(pdmesh_test::slurp(out / "mesh.msh"), Contains("\"region_7\"") && !Contains("\"domain\""));
  CHECK_THAT(pdmesh_test::slurp(out / "mesh.msh"), Contains("2 7 \"region_7\"\n"));
  CHECK_THAT(pdmesh_test::slurp(out / "mesh.mesh"), Contains("# ref 7: region region_7\n"));
}
