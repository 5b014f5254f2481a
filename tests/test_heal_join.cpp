// The "joined" healing rule (geometry/heal_join.hpp) on tests/data/heal/touch.crv and overlap.crv
// (tools/cases/make_heal_defects.py): a square sea whose diamond hole touches its outer side at a
// vertex, or crosses it by 100 m. Healing joins the hole to the outer ring through a neck about h wide;
// with geometry.heal = false the input stays exact and is refused as intersecting curves.
#include <catch2/catch.hpp>

#include <filesystem>
#include <string>

#include "core/errors.hpp"
#include "geometry/curve_reader.hpp"
#include "geometry/geometry.hpp"
#include "geometry/heal.hpp"
#include "json_check.hpp"
#include "run_pdmesh.hpp"
#include "temp_files.hpp"

using namespace pdmesh;

namespace {

std::string data(const std::string& name) { return std::string(PDMESH_SOURCE_DIR) + "/tests/data/heal/" + name; }

double min_angle(const std::string& json) {
  const std::string key = "\"included_angle\": {\"min\": ";
  const std::size_t at = json.find(key);
  REQUIRE(at != std::string::npos);
  return std::stod(json.substr(at + key.size()));
}

}  // namespace

TEST_CASE("a hole touching or crossing the outer ring: refused as given, joined into one ring by healing") {
  for (const char* file : {"touch.crv", "overlap.crv"}) {
    INFO(file);
    std::vector<RawCurve> curves = read_curve_file(data(file));
    REQUIRE(curves.size() == 2);
    CHECK_THROWS_AS(build_geometry(curves), GeometryError);
    const HealResult r = heal_curves(curves);
    CHECK(r.count(HealKind::Joined) == 1);
    REQUIRE(curves.size() == 1);
    const Geometry g = build_geometry(curves);
    // The sea less the diamond (2000 x 2000 / 2, less its 100 m tip outside the sea for overlap.crv)
    // and the neck's small wedges: within 1% of that.
    const double sea = 1e8 - 2e6 + (std::string(file) == "overlap.crv" ? 1e4 : 0.0);
    CHECK(g.area == Approx(sea).epsilon(0.01));
    CHECK(g.area < sea);
    const HealChange* w = r.worst(HealKind::Joined);
    REQUIRE(w != nullptr);
    CHECK(w->curve == "curve1");
    CHECK(w->at.y == Approx(0.0).margin(1.0));
    CHECK(w->size < w->h);
  }
}

TEST_CASE("pdmesh mesh on a touching and an overlapping hole: joined and reported, min angle >= 20") {
  for (const char* file : {"touch.crv", "overlap.crv"}) {
    INFO(file);
    const auto dir = pdmesh_test::fresh_dir(std::string("heal_join_") + file);
    const auto r = pdmesh_test::run_pdmesh("mesh '" + data(file) + "' --out '" + dir.string() + "'");
    INFO(r.output);
    REQUIRE(r.status == 0);
    CHECK(r.output.find("healing: 1 rings joined") != std::string::npos);
    const std::string json = pdmesh_test::slurp(dir / "quality.json");
    CHECK(json.find("\"joined\": 1") != std::string::npos);
    pdmesh_test::JsonCheck check;
    CHECK(check.valid(json));
    CHECK(min_angle(json) >= 20.0);
    CHECK(std::filesystem::exists(dir / "healing.png"));
    std::filesystem::remove_all(dir);
  }
}

TEST_CASE("geometry.heal = false: a touching or overlapping hole stays an intersect error, exit 2, nothing written") {
  for (const char* file : {"touch.crv", "overlap.crv"}) {
    INFO(file);
    const auto dir = pdmesh_test::fresh_dir(std::string("heal_join_off_") + file);
    const auto r =
        pdmesh_test::run_pdmesh("mesh '" + data(file) + "' --set geometry.heal=false --out '" + dir.string() + "'");
    INFO(r.output);
    CHECK(r.status == 2);
    CHECK(r.output.find("curves intersect") != std::string::npos);
    CHECK(!std::filesystem::exists(dir / "quality.json"));
    std::filesystem::remove_all(dir);
  }
}
