// The OpenFOAM polyMesh writer: counts, face order, orientation and closed cells, patches.
#include <catch2/catch.hpp>

#include <array>
#include <iterator>
#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include "core/errors.hpp"
#include "io/openfoam_writer.hpp"
#include "mixed_square.hpp"

using namespace pdmesh;

namespace {

struct V3 {
  double x = 0, y = 0, z = 0;
};
V3 operator-(V3 a, V3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
V3 operator+(V3 a, V3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
V3 cross(V3 a, V3 b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
double dot(V3 a, V3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }

// The list after a FoamFile header: its count, then the entries with '(' and ')' as blanks.
std::vector<std::string> entries(const std::string& file) {
  std::string body = file.substr(file.find("}\n") + 2);
  std::istringstream in(body);
  std::size_t count = 0;
  in >> count;
  std::string rest((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::vector<std::string> lines;
  std::istringstream rows(rest);
  std::string line;
  while (std::getline(rows, line))
    if (line != "(" && line != ")" && !line.empty()) lines.push_back(line);
  REQUIRE(lines.size() == count);
  return lines;
}

std::vector<double> numbers(std::string s) {
  for (char& ch : s)
    if (ch == '(' || ch == ')') ch = ' ';
  std::istringstream in(s);
  std::vector<double> out;
  double v;
  while (in >> v) out.push_back(v);
  return out;
}

}  // namespace

TEST_CASE("an OpenFOAM polyMesh: closed cells, normals from owner to neighbour, upper-triangular order",
          "[io][openfoam]") {
  const MixedMesh m = pdmesh_test::mixed_square();
  const OpenFoamFiles f = openfoam_files(m, {"bottom"}, {}, nullptr, 0.25);
  std::vector<V3> points;
  for (const std::string& p : entries(f.points)) {
    const auto v = numbers(p);
    REQUIRE(v.size() == 3);
    points.push_back({v[0], v[1], v[2]});
  }
  REQUIRE(points.size() == 12);
  CHECK(points[7].z == 0.25);
  CHECK(points[1].z == 0.0);
  std::vector<std::vector<int>> faces;
  for (const std::string& line : entries(f.faces)) {
    const auto v = numbers(line);
    std::vector<int> face;
    for (std::size_t k = 1; k < v.size(); ++k) face.push_back(static_cast<int>(v[k]));
    REQUIRE(face.size() == static_cast<std::size_t>(v[0]));
    faces.push_back(face);
  }
  std::vector<int> owner, neighbour;
  for (const std::string& line : entries(f.owner)) owner.push_back(std::stoi(line));
  for (const std::string& line : entries(f.neighbour)) neighbour.push_back(std::stoi(line));
  // 2 internal sides (quad | triangle 2, triangle 1 | triangle 2), 6 border sides, 3 fronts, 3 backs.
  REQUIRE(faces.size() == 14);
  REQUIRE(owner.size() == 14);
  REQUIRE(neighbour.size() == 2);
  CHECK(owner[0] == 0);
  CHECK(neighbour[0] == 2);
  CHECK(owner[1] == 1);
  CHECK(neighbour[1] == 2);
  // Each face's area vector (Newell), out of its owner and into its neighbour: every cell's faces sum
  // to zero (closed), and each points away from its owner's centre.
  std::vector<V3> sum(3), centre(3);
  for (std::size_t c = 0; c < 3; ++c) {
    const int corners = m.cells[c][3] < 0 ? 3 : 4;
    for (int k = 0; k < corners; ++k) {
      const auto p = m.points[static_cast<std::size_t>(m.cells[c][k])];
      centre[c] = centre[c] + V3{p.x / corners, p.y / corners, 0.125 / corners};
    }
  }
  for (std::size_t i = 0; i < faces.size(); ++i) {
    V3 area, mid;
    for (std::size_t k = 0; k < faces[i].size(); ++k) {
      const V3 a = points[static_cast<std::size_t>(faces[i][k])];
      const V3 b = points[static_cast<std::size_t>(faces[i][(k + 1) % faces[i].size()])];
      area = area + cross(a, b);
      mid = mid + V3{a.x / faces[i].size(), a.y / faces[i].size(), a.z / faces[i].size()};
    }
    CHECK(dot(area, mid - centre[static_cast<std::size_t>(owner[i])]) > 0);
    sum[static_cast<std::size_t>(owner[i])] = sum[static_cast<std::size_t>(owner[i])] + area;
    if (i < neighbour.size())
      sum[static_cast<std::size_t>(neighbour[i])] = sum[static_cast<std::size_t>(neighbour[i])] - area;
  }
  for (const V3& s : sum) CHECK(std::abs(s.x) + std::abs(s.y) + std::abs(s.z) < 1e-12);
  // Patches: the curves in order, bottom a wall, then the front and back.
  const std::string& b = f.boundary;
  CHECK(b.find("5\n(\n    bottom\n    {\n        type            wall;") != std::string::npos);
  CHECK(b.find("    right\n    {\n        type            patch;\n        inGroups        1(patch);\n"
               "        nFaces          1;\n        startFace       4;") != std::string::npos);
  CHECK(b.find("    frontAndBack\n    {\n        type            empty;\n        inGroups        1(empty);\n"
               "        nFaces          6;\n        startFace       8;") != std::string::npos);
}

TEST_CASE("the OpenFOAM writer refuses a border side on no curve and a side of three cells", "[io][openfoam]") {
  MixedMesh m = pdmesh_test::mixed_square();
  m.boundary_edges.pop_back();  // the left side
  CHECK_THROWS_AS(openfoam_files(m, {}), InputError);
  m = pdmesh_test::mixed_square();
  m.cells.push_back({1, 4, 3, -1});  // a third cell on the side 1-4... and on 3-4, 1-3
  CHECK_THROWS_AS(openfoam_files(m, {}), InputError);
}

TEST_CASE("an OpenFOAM patch per physical group of curves, in the order of their tags", "[io][openfoam]") {
  const MixedMesh m = pdmesh_test::mixed_square();
  // right and left in one group of tag 5; bottom and top take the free tags 1 and 2.
  const OpenFoamFiles f = openfoam_files(m, {"left"}, {{5, "sides", {1, 3}}});
  const std::string& b = f.boundary;
  const auto at = [&](const std::string& name) { return b.find("    " + name + "\n    {"); };
  REQUIRE(at("bottom") != std::string::npos);
  REQUIRE(at("top") != std::string::npos);
  REQUIRE(at("sides") != std::string::npos);
  CHECK(at("bottom") < at("top"));
  CHECK(at("top") < at("sides"));
  CHECK(b.find("4\n(") != std::string::npos);  // three groups and frontAndBack
  CHECK(b.find("    sides\n    {\n        type            wall;\n        inGroups        1(wall);\n"
               "        nFaces          2;\n        startFace       6;") != std::string::npos);
  CHECK(b.find("right") == std::string::npos);
}

TEST_CASE("OpenFOAM cellZones list each zone's cells, and a mesh without zones has none", "[io][openfoam]") {
  const MixedMesh m = pdmesh_test::mixed_square();
  CHECK(openfoam_files(m, {}).cell_zones.empty());
  const OpenFoamZones zones{{"steel", "copper wire"}, {1, 0, 1}};
  const std::string z = openfoam_files(m, {}, {}, &zones).cell_zones;
  CHECK(z.find("object      cellZones;") != std::string::npos);
  CHECK(z.find("2\n(\nsteel\n{\n    type cellZone;\ncellLabels      List<label> \n1\n(\n1\n)\n;\n}\n") !=
        std::string::npos);
  CHECK(z.find("copper_wire\n{\n    type cellZone;\ncellLabels      List<label> \n2\n(\n0\n2\n)\n;\n}\n") !=
        std::string::npos);
  const OpenFoamZones short_list{{"steel"}, {0, 0}};
  CHECK_THROWS_AS(openfoam_files(m, {}, {}, &short_list), InputError);
}
