// The node-string formats: fort.14 (ADCIRC/SCHISM) and .2dm (SMS), on a hand-made mesh of a square
// with a square island, one open side and an embedded constraint edge.
#include <catch2/catch.hpp>

#include <sstream>
#include <string>
#include <vector>

#include "io/boundary_strings.hpp"
#include "io/fort14_writer.hpp"
#include "io/sms2dm_writer.hpp"
#include "temp_files.hpp"

using namespace pdmesh;
using pdmesh_test::lines_of;

namespace {

// Outer square 0..3 (points 0-3 counter-clockwise), island 1..2 (points 4-7 counter-clockwise), eight
// counter-clockwise triangles between them. Curves: "ocean" the right side 1-2, "coast" 2-3-0-1,
// "island" 4-5-6-7-4 (stored counter-clockwise, so the writers must reverse it to keep the domain on
// the left), "levee" the interior edge 0-5.
Mesh island_mesh() {
  Mesh m;
  m.points = {{0, 0}, {3, 0}, {3, 3}, {0, 3}, {1, 1}, {2, 1}, {2, 2}, {1, 2}};
  m.triangles = {{0, 1, 5}, {0, 5, 4}, {1, 2, 6}, {1, 6, 5}, {2, 3, 7}, {2, 7, 6}, {3, 0, 4}, {3, 4, 7}};
  m.curve_names = {"ocean", "coast", "island", "levee"};
  m.boundary_edges = {{1, 2, 0}, {2, 3, 1}, {3, 0, 1}, {0, 1, 1}, {4, 5, 2},
                      {5, 6, 2}, {6, 7, 2}, {7, 4, 2}, {0, 5, 3}};
  return m;
}

}  // namespace

TEST_CASE("boundary strings run with the domain on the left and know islands") {
  const auto strings = boundary_strings(island_mesh());
  REQUIRE(strings.size() == 3);  // the levee has triangles on both sides: not a boundary
  CHECK(strings[0].curve == 0);
  CHECK(strings[0].nodes == std::vector<int>{1, 2});
  CHECK_FALSE(strings[0].internal);
  CHECK_FALSE(strings[0].closed);
  CHECK(strings[1].nodes == std::vector<int>{2, 3, 0, 1});
  CHECK_FALSE(strings[1].internal);
  CHECK(strings[2].curve == 2);
  CHECK(strings[2].nodes == std::vector<int>{4, 7, 6, 5, 4});
  CHECK(strings[2].internal);
  CHECK(strings[2].closed);
}

TEST_CASE("fort.14 holds the nodes, elements, open and land boundaries") {
  const auto lines = lines_of(fort14_string(island_mesh(), {"ocean"}));
  REQUIRE(lines.size() == 2 + 8 + 8 + 2 + 1 + 2 + 2 + 1 + 4 + 1 + 5);
  CHECK(lines[1] == "8 8");  // NE NP, bare: some readers take the line as two integers
  CHECK(lines[2] == "1 0 0 0");
  CHECK(lines[4] == "3 3 3 0");
  CHECK(lines[10] == "1 3 1 2 6");  // triangle 0 = (0, 1, 5), 1-based
  CHECK(lines[18] == "1 = Number of open boundaries");
  CHECK(lines[19] == "2 = Total number of open boundary nodes");
  CHECK(lines[20].rfind("2 0 = ", 0) == 0);
  CHECK(lines[21] == "2");
  CHECK(lines[22] == "3");
  CHECK(lines[23] == "2 = Number of land boundaries");
  CHECK(lines[24] == "9 = Total number of land boundary nodes");
  CHECK(lines[25].rfind("4 0 = ", 0) == 0);  // the coast: outer, IBTYPE 0
  CHECK(lines[26] == "3");
  CHECK(lines[29] == "2");
  CHECK(lines[30].rfind("5 1 = ", 0) == 0);  // the island: internal, IBTYPE 1, closed
  CHECK(lines[31] == "5");
  CHECK(lines[32] == "8");
  CHECK(lines[35] == "5");
}

TEST_CASE("fort.14 without open boundaries lists every curve as land") {
  const auto lines = lines_of(fort14_string(island_mesh(), {}));
  CHECK(lines[18] == "0 = Number of open boundaries");
  CHECK(lines[19] == "0 = Total number of open boundary nodes");
  CHECK(lines[20] == "3 = Number of land boundaries");
  CHECK(lines[21] == "11 = Total number of land boundary nodes");
}

TEST_CASE("2dm holds elements, nodes and named node strings") {
  const auto lines = lines_of(sms2dm_string(island_mesh()));
  REQUIRE(lines.size() == 3 + 8 + 8 + 3);
  CHECK(lines[0] == "MESH2D");
  CHECK(lines[3] == "E3T 1 1 2 6 1");
  CHECK(lines[11] == "ND 1 0 0 0");
  CHECK(lines[19] == "NS 2 -3 ocean");
  CHECK(lines[20] == "NS 3 4 1 -2 coast");
  CHECK(lines[21] == "NS 5 8 7 6 -5 island");
}

TEST_CASE("2dm wraps a node string after ten ids") {
  Mesh m;
  for (int i = 0; i < 12; ++i) m.points.push_back({static_cast<double>(i), 0.0});
  m.points.push_back({5.5, 1.0});
  m.curve_names = {"bottom"};
  for (int i = 0; i < 11; ++i) {
    m.triangles.push_back({i, i + 1, 12});
    m.boundary_edges.push_back({i, i + 1, 0});
  }
  const auto lines = lines_of(sms2dm_string(m));
  CHECK(lines[lines.size() - 2] == "NS 1 2 3 4 5 6 7 8 9 10");
  CHECK(lines.back() == "NS 11 -12 bottom");
}
