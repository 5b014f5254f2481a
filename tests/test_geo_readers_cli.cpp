// `pdmesh mesh` on the geometry users bring (issue 39): a Selig airfoil file, a GeoJSON file and a
// shapefile mesh end to end, and lon/lat data comes back in lon/lat with geometry.projection.
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "run_pdmesh.hpp"
#include "temp_files.hpp"

namespace fs = std::filesystem;

namespace {

std::string data(const std::string& name) { return std::string(PDMESH_SOURCE_DIR "/tests/data/geometry/") + name; }

pdmesh_test::Result mesh(const std::string& inputs, const fs::path& out, const std::string& options = "") {
  return pdmesh_test::run_pdmesh("mesh " + inputs + " --out '" + out.string() +
                                 "' --device host --iterations 0 --formats msh,triangle -q " + options);
}

// The points of a Triangle .node file: '#' comment lines, "N 2 A M", then "i x y [A attributes] [marker]".
std::vector<std::pair<double, double>> node_points(const fs::path& file) {
  std::ifstream in(file);
  std::string text, line;
  while (std::getline(in, line))
    if (line.empty() || line[0] != '#') text += line + "\n";
  std::istringstream s(text);
  std::size_t n = 0;
  int dim = 0, attributes = 0, markers = 0;
  s >> n >> dim >> attributes >> markers;
  std::vector<std::pair<double, double>> pts(n);
  for (auto& p : pts) {
    double skip = 0;
    s >> skip >> p.first >> p.second;
    for (int k = 0; k < attributes + markers; ++k) s >> skip;
  }
  return pts;
}

}  // namespace

TEST_CASE("pdmesh mesh on a Selig airfoil file names the physical groups upper, lower, te", "[cli][airfoil]") {
  const fs::path out = pdmesh_test::fresh_path("cli_airfoil");
  const auto r = mesh("'" + data("airfoils/naca2412.dat") + "'", out);
  INFO(r.output);
  REQUIRE(r.status == 0);
  const std::string msh = pdmesh_test::slurp(out / "mesh.msh");
  CHECK(msh.find("\"upper\"") != std::string::npos);
  CHECK(msh.find("\"lower\"") != std::string::npos);
  CHECK(msh.find("\"te\"") != std::string::npos);
  fs::remove_all(out);
}

TEST_CASE("pdmesh mesh on GeoJSON and on a shapefile of the same polygons", "[cli][geojson][shapefile]") {
  for (const std::string file : {"gis/lake.geojson", "gis/lake.shp"}) {
    INFO(file);
    const fs::path out = pdmesh_test::fresh_path("cli_gis");
    const auto r = mesh("'" + data(file) + "'", out);
    INFO(r.output);
    REQUIRE(r.status == 0);
    const std::string msh = pdmesh_test::slurp(out / "mesh.msh");
    CHECK(msh.find("\"lake_shore_hole1\"") != std::string::npos);
    CHECK(msh.find("\"islet\"") != std::string::npos);
    fs::remove_all(out);
  }
}

TEST_CASE("geometry.projection = equirectangular writes lon/lat mesh files", "[cli][projection]") {
  const fs::path out = pdmesh_test::fresh_path("cli_projection");
  const std::string input = "'" + data("gis/lonlat_square.geojson") + "'";
  // Metres: the box is about 7.2 km x 11.1 km, so a 1 km spacing makes a small mesh.
  const auto r = mesh(input, out, "--set geometry.projection=equirectangular --set spacing.expression=1000");
  INFO(r.output);
  REQUIRE(r.status == 0);
  const auto pts = node_points(out / "mesh.node");
  REQUIRE(pts.size() > 50);
  double lo_x = 1e9, hi_x = -1e9, lo_y = 1e9, hi_y = -1e9;
  for (const auto& [x, y] : pts) {
    lo_x = std::min(lo_x, x);
    hi_x = std::max(hi_x, x);
    lo_y = std::min(lo_y, y);
    hi_y = std::max(hi_y, y);
  }
  CHECK(lo_x == Approx(10.0).margin(1e-9));
  CHECK(hi_x == Approx(10.1).margin(1e-9));
  CHECK(lo_y == Approx(50.0).margin(1e-9));
  CHECK(hi_y == Approx(50.1).margin(1e-9));
  fs::remove_all(out);
}
