// Mesh pictures filled by region (render/region_fill): the palette's colours in the triangles and the
// legend, the interfaces between regions drawn thick, output.color_by = "region" and --color-by region.
#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "app/config/case_file.hpp"
#include "core/errors.hpp"
#include "render/mesh_picture.hpp"
#include "render/region_fill.hpp"
#include "png_pixels.hpp"
#include "run_pdmesh.hpp"
#include "source_dir.hpp"
#include "temp_files.hpp"

namespace fs = std::filesystem;
using namespace pdmesh;
using pdmesh_test::Png;

namespace {

// The rectangle [0, 2] x [0, 1] as two unit squares, each split along its diagonal from its lower
// left corner: triangles 0 and 1 in the left square (attribute 1, "steel"), 2 and 3 in the right one
// (attribute 2, no name). The squares' common edge x = 1 (points 1 and 4) is not a boundary edge.
Mesh two_squares() {
  Mesh m;
  m.points = {{0, 0}, {1, 0}, {2, 0}, {2, 1}, {1, 1}, {0, 1}};
  m.triangles = {{0, 1, 4}, {0, 4, 5}, {1, 2, 3}, {1, 3, 4}};
  m.boundary_edges = {{0, 1, 0}, {1, 2, 0}, {2, 3, 0}, {3, 4, 0}, {4, 5, 0}, {5, 0, 0}};
  m.curve_names = {"outline"};
  m.region = {1, 1, 2, 2};
  m.region_names = {{1.0, "steel"}};
  return m;
}

bool near(const Rgb& pixel, const Rgb& colour) {
  return std::abs(pixel.r - 255 * colour.r) <= 2 && std::abs(pixel.g - 255 * colour.g) <= 2 &&
         std::abs(pixel.b - 255 * colour.b) <= 2;
}

// How many pixels of a picture have `colour`.
int pixels_of(const Png& png, const Rgb& colour) {
  int n = 0;
  for (int y = 0; y < png.height(); ++y)
    for (int x = 0; x < png.width(); ++x) n += near(png.pixel(x, y), colour);
  return n;
}

// The picture pixel of world point w in a 400-pixel-wide picture of two_squares() (window
// [-0.06, 2.06] x [-0.06, 1.06], scale 400 / 2.12, a 40-pixel title band).
std::pair<int, int> pixel_of(Vec2 w) {
  const double scale = 400 / 2.12;
  return {static_cast<int>((w.x + 0.06) * scale), static_cast<int>(40 + (1.06 - w.y) * scale)};
}

}  // namespace

TEST_CASE("the region legend names each attribute's region, in ascending order, and the triangles outside",
          "[render][region]") {
  Mesh m = two_squares();
  m.region = {2, 0, 1, 2};
  const RegionFill fill = region_fill(m);
  REQUIRE(fill.entries.size() == 3);
  CHECK(fill.entries[0].label == "steel");
  CHECK(fill.entries[0].triangles == 1);
  CHECK(fill.entries[1].label == "attribute 2");
  CHECK(fill.entries[1].triangles == 2);
  CHECK(fill.entries[2].label == "no region");
  CHECK(fill.entries[2].attribute == 0.0);
  CHECK(near({255 * fill.entries[1].colour.r, 255 * fill.entries[1].colour.g, 255 * fill.entries[1].colour.b},
             region_palette_colour(1)));
  CHECK(fill.groups.order == std::vector<std::uint32_t>{2, 0, 3, 1});
  CHECK(fill.groups.ends == std::vector<std::size_t>{1, 3, 4});
  CHECK(fill.groups.colours.size() == 3);
  CHECK(fill.has_regions());
  // More regions than colours: the palette cycles.
  CHECK(
      near({255 * region_palette_colour(region_palette_size()).r, 255 * region_palette_colour(region_palette_size()).g,
            255 * region_palette_colour(region_palette_size()).b},
           region_palette_colour(0)));
  // A mesh without regions: one grey "no region" entry of every triangle.
  m.region.clear();
  const RegionFill none = region_fill(m);
  REQUIRE(none.entries.size() == 1);
  CHECK(none.entries[0].label == "no region");
  CHECK(none.entries[0].triangles == 4);
  CHECK_FALSE(none.has_regions());
  m.region = {1, 2};
  CHECK_THROWS_AS(region_fill(m), Error);
}

TEST_CASE("the interfaces between regions are the edges between triangles of different attributes, but boundary edges",
          "[render][region]") {
  Mesh m = two_squares();
  CHECK(region_interfaces(m) == std::vector<std::pair<int, int>>{{1, 4}});
  // A constraint along the interface is a boundary edge, drawn thick already.
  m.boundary_edges.push_back({4, 1, 1});
  CHECK(region_interfaces(m).empty());
  m.boundary_edges.pop_back();
  // One region, or none: no interfaces.
  m.region = {3, 3, 3, 3};
  CHECK(region_interfaces(m).empty());
  m.region.clear();
  CHECK(region_interfaces(m).empty());
}

TEST_CASE("a two-region mesh's picture filled by region shows each region in its palette colour, with a legend",
          "[render][region]") {
  const fs::path dir = pdmesh_test::fresh_dir("region_picture");
  const Mesh m = two_squares();
  MeshPictureOptions o;
  o.title = "two squares";
  o.long_side = 400;
  o.fill_regions = true;
  write_mesh_picture(dir / "mesh.png", m, o);
  write_mesh_picture(dir / "mesh.svg", m, o);
  CHECK(fs::file_size(dir / "mesh.svg") > 0);
  const Png png(dir / "mesh.png");
  REQUIRE(png.ok());
  const int plot_right = 400;
  CHECK(png.width() > plot_right + 60);  // the legend's band
  const Rgb steel = region_palette_colour(0), second = region_palette_colour(1);
  for (const Vec2 w : {Vec2{0.8, 0.2}, Vec2{0.2, 0.8}}) {
    const auto [x, y] = pixel_of(w);
    CHECK(near(png.pixel(x, y), steel));
  }
  for (const Vec2 w : {Vec2{1.8, 0.2}, Vec2{1.2, 0.8}}) {
    const auto [x, y] = pixel_of(w);
    CHECK(near(png.pixel(x, y), second));
  }
  // The interface x = 1 is drawn: black between the two fills.
  const auto [ix, iy] = pixel_of({1.0, 0.5});
  CHECK(png.pixel(ix, iy).r < 80);
  // The legend's swatches, one row each below the caption, in the band right of the plot.
  CHECK(near(png.pixel(plot_right + 28, 40 + 44 - 5), steel));
  CHECK(near(png.pixel(plot_right + 28, 40 + 66 - 5), second));
  CHECK(pixels_of(png, steel) > 10000);
  CHECK(pixels_of(png, second) > 10000);
  fs::remove_all(dir);
}

TEST_CASE("a picture filled by region of a mesh without regions is grey, and both fills at once are refused",
          "[render][region]") {
  const fs::path dir = pdmesh_test::fresh_dir("region_none");
  Mesh m = two_squares();
  m.region.clear();
  m.region_names.clear();
  MeshPictureOptions o;
  o.long_side = 400;
  o.fill_regions = true;
  write_mesh_picture(dir / "mesh.png", m, o);
  const Png png(dir / "mesh.png");
  REQUIRE(png.ok());
  const auto [x, y] = pixel_of({0.8, 0.2});
  CHECK(near(png.pixel(x, y), kNoRegion));
  CHECK(pixels_of(png, region_palette_colour(0)) == 0);
  const std::vector<double> values = {1, 2, 3, 4};
  o.triangle_values = &values;
  CHECK_THROWS_AS(write_mesh_picture(dir / "both.png", m, o), Error);
  CHECK_FALSE(fs::exists(dir / "both.png"));
  fs::remove_all(dir);
}

TEST_CASE("a default picture draws a multi-region mesh's interfaces thick and a one-region mesh as one without regions",
          "[render][region]") {
  const fs::path dir = pdmesh_test::fresh_dir("region_default");
  MeshPictureOptions o;
  o.long_side = 400;
  Mesh plain = two_squares();
  plain.region.clear();
  plain.region_names.clear();
  write_mesh_picture(dir / "plain.png", plain, o);
  Mesh one = two_squares();
  one.region = {1, 1, 1, 1};
  write_mesh_picture(dir / "one.png", one, o);
  write_mesh_picture(dir / "two.png", two_squares(), o);
  CHECK(pdmesh_test::slurp(dir / "one.png") == pdmesh_test::slurp(dir / "plain.png"));
  // Two regions: the interface x = 1 is 2 pixels wide, the thin edge's 0.6 pixel is not.
  const Png plain_png(dir / "plain.png"), two_png(dir / "two.png");
  REQUIRE(two_png.ok());
  const auto [ix, iy] = pixel_of({1.0, 0.5});
  int plain_dark = 0, two_dark = 0;
  for (int x = ix - 3; x <= ix + 3; ++x) {
    plain_dark += plain_png.pixel(x, iy).r < 128;
    two_dark += two_png.pixel(x, iy).r < 128;
  }
  CHECK(plain_dark <= 1);
  CHECK(two_dark >= 2);
  fs::remove_all(dir);
}

TEST_CASE("output.color_by takes region beside the metrics and refuses other names", "[render][region][case]") {
  const std::string base = "[geometry]\nfiles = [\"a.crv\"]\n[output]\ncolor_by = ";
  CHECK(parse_case_text(base + "\"region\"\n", "/cases/demo/case.toml", {}).output.color_by == "region");
  CHECK(parse_case_text(base + "\"min_angle\"\n", "/cases/demo/case.toml", {}).output.color_by == "min_angle");
  try {
    parse_case_text(base + "\"regions\"\n", "/cases/demo/case.toml", {});
    FAIL("output.color_by = \"regions\" was accepted");
  } catch (const InputError& e) {
    CHECK_THAT(e.what(), Catch::Contains("output.color_by must be one of none, min_angle") &&
                             Catch::Contains("min_jacobian, region, got 'regions'"));
  }
}

TEST_CASE("pdmesh mesh --color-by region fills mesh.png by the .poly's regions, and quality by a file's",
          "[render][region][cli]") {
  const fs::path dir = pdmesh_test::fresh_dir("region_run");
  const fs::path case_file = fs::path(pdmesh::test::source_dir()) / "tests/data/interop/two_regions.toml";
  const pdmesh_test::Result run = pdmesh_test::run_pdmesh("mesh '" + case_file.string() + "' --out '" + dir.string() +
                                                          "' --iterations 20 --formats msh,png --color-by region -q");
  INFO(run.output);
  REQUIRE(run.status == 0);
  {
    const Png png(dir / "mesh.png");
    REQUIRE(png.ok());
    CHECK(pixels_of(png, region_palette_colour(0)) > 1000);
    CHECK(pixels_of(png, region_palette_colour(1)) > 1000);
  }
  const pdmesh_test::Result quality = pdmesh_test::run_pdmesh(
      "quality '" + (dir / "mesh.msh").string() + "' --picture '" + (dir / "q.png").string() + "' --color-by region");
  INFO(quality.output);
  REQUIRE(quality.status == 0);
  {
    const Png png(dir / "q.png");
    REQUIRE(png.ok());
    CHECK(pixels_of(png, region_palette_colour(0)) > 1000);
    CHECK(pixels_of(png, region_palette_colour(1)) > 1000);
  }
  const pdmesh_test::Result bad =
      pdmesh_test::run_pdmesh("quality '" + (dir / "mesh.msh").string() + "' --picture '" + (dir / "r.png").string() +
                              "' --color-by region --color-range 0,1");
  CHECK(bad.status == 2);
  CHECK(bad.output.find("--color-range needs --color-by METRIC") != std::string::npos);
  const pdmesh_test::Result unknown =
      pdmesh_test::run_pdmesh("mesh '" + case_file.string() + "' --out '" + dir.string() + "/x' --color-by regions -q");
  CHECK(unknown.status == 2);
  CHECK(unknown.output.find("got 'regions'") != std::string::npos);
  fs::remove_all(dir);
}
