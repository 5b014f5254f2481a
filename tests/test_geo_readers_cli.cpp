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

TEST_CASE("geometry.projection with a boundary layer: the mixed mesh is written in lon/lat", "[cli][projection]") {
  // The layer fronts are already projected: the core must not project them again (they are metres,
  // not lon/lat), and the mixed mesh's file must be mapped back like the triangle meshes'.
  const fs::path dir = pdmesh_test::fresh_dir("cli_projection_layers");
  std::ofstream(dir / "island.geojson")
      << "{\"type\": \"Feature\", \"properties\": {\"name\": \"sea\"}, \"geometry\": {\"type\": \"Polygon\", "
         "\"coordinates\": [[[10.0, 50.0], [10.1, 50.0], [10.1, 50.1], [10.0, 50.1], [10.0, 50.0]], "
         "[[10.04, 50.04], [10.06, 50.04], [10.06, 50.06], [10.04, 50.06], [10.04, 50.04]]]}}\n";
  std::ofstream(dir / "case.toml")
      << "geometry.files = [\"island.geojson\"]\ngeometry.projection = \"equirectangular\"\n"
         "spacing.expression = \"400\"\n[[boundary_layer]]\ncurves = [\"sea_hole1\"]\n"
         "first_height = 20\ngrowth = 1.2\nthickness = 200\nelements = \"quads\"\n";
  const auto r = pdmesh_test::run_pdmesh("mesh '" + (dir / "case.toml").string() + "' --out '" +
                                         (dir / "out").string() + "' --device host --iterations 0 --formats msh -q");
  INFO(r.output);
  REQUIRE(r.status == 0);
  // Gmsh 4.1 $Nodes: a header "blocks nodes min max", one block "dim tag parametric n", its n tags,
  // then its n coordinate lines.
  std::istringstream msh(pdmesh_test::slurp(dir / "out" / "mesh.msh"));
  std::string word;
  while (msh >> word && word != "$Nodes") {
  }
  std::size_t blocks = 0, n = 0, lo = 0, hi = 0, parametric = 0;
  int dim = 0, tag = 0;
  msh >> blocks >> n >> lo >> hi >> dim >> tag >> parametric >> n;
  REQUIRE(blocks == 1);
  REQUIRE(n > 100);
  for (std::size_t k = 0; k < n; ++k) msh >> lo;
  double min_x = 1e9, max_x = -1e9, min_y = 1e9, max_y = -1e9;
  for (std::size_t k = 0; k < n; ++k) {
    double x = 0, y = 0, z = 0;
    msh >> x >> y >> z;
    min_x = std::min(min_x, x);
    max_x = std::max(max_x, x);
    min_y = std::min(min_y, y);
    max_y = std::max(max_y, y);
  }
  CHECK(min_x == Approx(10.0).margin(1e-9));
  CHECK(max_x == Approx(10.1).margin(1e-9));
  CHECK(min_y == Approx(50.0).margin(1e-9));
  CHECK(max_y == Approx(50.1).margin(1e-9));
  fs::remove_all(dir);
}
