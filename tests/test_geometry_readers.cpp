// Geometry file readers (.crv/.dat, .poly) and read_geometry(): good files and every error case.
#include <catch2/catch.hpp>

#include <filesystem>

#include "core/errors.hpp"
#include "geometry/curve_reader.hpp"
#include "geometry/geometry.hpp"

using namespace pdmesh;
using Catch::Matchers::Contains;

namespace {

std::string data(const std::string& name) { return std::string(PDMESH_SOURCE_DIR "/tests/data/geometry/") + name; }

const std::string k30p30n = PDMESH_SOURCE_DIR "/../shared/data/30p30n/2010_30p30n_thik_te_18inches.crv.dat";
const std::string k30p30nExcerpt = data("30p30n_flap.crv");

}  // namespace

TEST_CASE("crv reader: unit square with comments and optional z", "[geometry]") {
  const auto raw = read_curve_file(data("unit_square.crv"));
  REQUIRE(raw.size() == 4);
  CHECK(raw[0].points.size() == 2);
  CHECK(raw[0].line == 3);
  CHECK(raw[0].lines == std::vector<int>{3, 4});
  CHECK(raw[1].lines == std::vector<int>{7, 8});
  CHECK(raw[2].points[1] == Vec2{0, 1});
  CHECK(raw[0].file == data("unit_square.crv"));
  const Geometry g = build_geometry(raw);
  CHECK(g.area == 1.0);
  CHECK(g.critical.size() == 4);
}

TEST_CASE("crv reader: the 30P30N high-lift airfoil makes 3 clockwise loops of 11 curves", "[geometry]") {
  const std::string path = std::filesystem::exists(k30p30n) ? k30p30n : k30p30nExcerpt;
  const auto raw = read_curve_file(path);
  const Geometry g = build_geometry(raw);
  if (path == k30p30n) {
    REQUIRE(raw.size() == 11);
    CHECK(raw[3].points.size() == 401);
    REQUIRE(g.loops.size() == 3);
    CHECK(g.loops[0].curves == std::vector<int>{0, 1, 2, 3, 4});
    CHECK(g.loops[1].curves == std::vector<int>{5, 6, 7});
    CHECK(g.loops[2].curves == std::vector<int>{8, 9, 10});
    CHECK(g.segments.size() == 1067u - 11u);  // 1078 lines - 11 count lines = 1067 points
  }
  for (const Loop& loop : g.loops) {
    CHECK(loop.signed_area < 0);  // clockwise
    CHECK(loop.depth == 0);
  }
  CHECK(g.area > 0);
}

TEST_CASE("crv reader errors", "[geometry]") {
  CHECK_THROWS_WITH(read_curve_file(data("no_such_file.crv")),
                    Contains("cannot open") && Contains("no_such_file.crv"));
  CHECK_THROWS_WITH(read_curve_file(data("")), Contains("directory"));
  CHECK_THROWS_WITH(read_curve_file(data("empty.crv")), Contains("empty.crv") && Contains("no curves"));
  CHECK_THROWS_WITH(read_curve_file(data("comments_only.crv")), Contains("no curves"));
  CHECK_THROWS_WITH(read_curve_file(data("garbage.crv")), Contains("garbage.crv:4") && Contains("not text"));
  CHECK_THROWS_WITH(read_curve_file(data("truncated.crv")),
                    Contains("truncated.crv:4") && Contains("block of 5 points is truncated") &&
                        Contains("only 3 lines"));
  CHECK_THROWS_WITH(read_curve_file(data("negative_count.crv")),
                    Contains("negative_count.crv:1") && Contains("'-3' is negative"));
  CHECK_THROWS_WITH(read_curve_file(data("fractional_count.crv")),
                    Contains("fractional_count.crv:1") && Contains("'2.5' is not a non-negative integer"));
  CHECK_THROWS_WITH(read_curve_file(data("nan.crv")), Contains("nan.crv:3") && Contains("'nan' is not finite"));
  CHECK_THROWS_WITH(read_curve_file(data("inf.crv")), Contains("inf.crv:4") && Contains("'-inf' is not finite"));
  CHECK_THROWS_WITH(read_curve_file(data("huge.crv")), Contains("huge.crv:3") && Contains("'1e308' is too large"));
  CHECK_THROWS_WITH(read_curve_file(data("extra_tokens.crv")),
                    Contains("extra_tokens.crv:3") && Contains("extra text '7'"));
  CHECK_THROWS_WITH(read_curve_file(data("bad_number.crv")),
                    Contains("bad_number.crv:3") && Contains("'0x' is not a number"));
  CHECK_THROWS_WITH(read_curve_file(data("count_too_large.crv")),
                    Contains("count_too_large.crv:6") && Contains("found '2'") && Contains("line 1"));
  // A one-point curve reads fine; build_geometry rejects it with the file and line.
  CHECK_THROWS_WITH(build_geometry(read_curve_file(data("one_point.crv"))),
                    Contains("one_point.crv:2") && Contains("1 point"));
}

TEST_CASE("crv reader: the 30P30N flap excerpt is one clockwise loop", "[geometry]") {
  const Geometry g = build_geometry(read_curve_file(k30p30nExcerpt));
  REQUIRE(g.curves.size() == 3);
  REQUIRE(g.loops.size() == 1);
  CHECK(g.loops[0].signed_area < 0);
  CHECK(g.segments.size() == 100u + 100u + 4u);
  CHECK(g.critical.size() >= 3);
}
