// Tests of the pictures: valid PNG/SVG files of the right size, colours where things were drawn,
// no temporary files left behind.
#include <catch2/catch.hpp>

#include <cairo.h>
#include <unistd.h>

#include <filesystem>
#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <sstream>

#include "core/errors.hpp"
#include "mesh/quality.hpp"
#include "render/canvas.hpp"
#include "render/mesh_picture.hpp"
#include "render/metric_picture.hpp"
#include "render/node_picture.hpp"
#include "png_pixels.hpp"
#include "temp_files.hpp"

namespace fs = std::filesystem;
using namespace pdmesh;

namespace {

fs::path fresh_dir(const std::string& tag) { return pdmesh_test::fresh_dir("render_" + tag); }
using pdmesh_test::entries;
using pdmesh_test::slurp;

using pdmesh_test::Png;

// How many pixels of two pictures of the same size differ in any channel.
int differing_pixels(const Png& one, const Png& other) {
  int differing = 0;
  for (int y = 0; y < one.height(); ++y)
    for (int x = 0; x < one.width(); ++x) {
      const Rgb a = one.pixel(x, y), b = other.pixel(x, y);
      differing += a.r != b.r || a.g != b.g || a.b != b.b;
    }
  return differing;
}

// The unit square [0, 2] x [0, 1] as four segments (only what pictures use).
Geometry rectangle_geometry() {
  Geometry g;
  const Vec2 c[4] = {{0, 0}, {2, 0}, {2, 1}, {0, 1}};
  for (int k = 0; k < 4; ++k) {
    Segment s;
    s.a = c[k];
    s.b = c[(k + 1) % 4];
    s.curve = 0;
    s.index = k;
    s.length = dist(s.a, s.b);
    g.segments.push_back(s);
    g.extents.add(c[k]);
  }
  return g;
}

const char kPngSignature[] = "\x89PNG\r\n\x1a\n";

// The unit square as two triangles split along its diagonal from (0, 0) to (1, 1): the first one
// lower right, the second upper left.
Mesh unit_square_mesh() {
  Mesh m;
  m.points = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  m.triangles = {{0, 1, 2}, {0, 2, 3}};
  m.boundary_edges = {{0, 1, 0}, {1, 2, 0}, {2, 3, 0}, {3, 0, 0}};
  m.curve_names = {"square"};
  return m;
}

// The unit square as a k x k grid of cells split along their diagonals (2 k^2 triangles), its
// points mapped by `map` (a monotone map of [0, 1]^2 onto itself keeps the square).
template <class Map>
Mesh grid_mesh(int k, Map map) {
  Mesh m;
  for (int j = 0; j <= k; ++j)
    for (int i = 0; i <= k; ++i) m.points.push_back(map(static_cast<double>(i) / k, static_cast<double>(j) / k));
  const auto id = [&](int i, int j) { return j * (k + 1) + i; };
  for (int j = 0; j < k; ++j)
    for (int i = 0; i < k; ++i) {
      m.triangles.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      m.triangles.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  m.boundary_edges = {
      {id(0, 0), id(k, 0), 0}, {id(k, 0), id(k, k), 0}, {id(k, k), id(0, k), 0}, {id(0, k), id(0, 0), 0}};
  m.curve_names = {"square"};
  return m;
}

// World [0, 200]^2 on a 200 x 200 plot without a title band: world (x, y) is pixel (x, 200 - y).
CanvasOptions plot_200() {
  CanvasOptions options;
  options.window = Box{{0, 0}, {200, 200}};
  options.long_side = 200;
  options.title_height = 0;
  return options;
}

// The red channel of picture pixel (x, y) of a canvas, 0-255.
int red_at(Canvas& c, int x, int y) {
  cairo_surface_flush(c.surface());
  const unsigned char* row =
      cairo_image_surface_get_data(c.surface()) + (y - c.first_row()) * cairo_image_surface_get_stride(c.surface());
  return static_cast<int>((*reinterpret_cast<const std::uint32_t*>(row + 4 * x) >> 16) & 255);
}

}  // namespace

TEST_CASE("padded windows add 3% of the longer side", "[render]") {
  const Box w = padded_window(Box{{0, 0}, {2, 1}});
  CHECK(w.lo.x == Approx(-0.06));
  CHECK(w.hi.x == Approx(2.06));
  CHECK(w.lo.y == Approx(-0.06));
  CHECK(w.hi.y == Approx(1.06));
  const Box point = padded_window(Box{{3, 3}, {3, 3}});
  CHECK(point.width() > 0);
  CHECK(point.contains({3, 3}));
}

TEST_CASE("node pictures are PNGs of the documented size with nodes and geometry in their colours", "[render]") {
  const fs::path dir = fresh_dir("nodes");
  const Geometry g = rectangle_geometry();
  NodeSet n;
  n.add({0, 0}, 0.2, NodeKind::Fixed, 0);
  n.add({1, 0}, 0.2, NodeKind::Boundary, 0);
  n.add({1, 0.5}, 0.2, NodeKind::Interior, -1);
  std::vector<Box> quads = {Box{{0, 0}, {1, 1}}, Box{{1, 0}, {2, 1}}};
  NodePictureOptions o;
  o.title = "rectangle - initial";
  o.tree_quads = &quads;
  write_node_picture(dir / "initial.png", g, n, o);
  write_node_picture(dir / "initial.svg", g, n, o);
  CHECK(entries(dir) == 2);  // no temporaries

  const std::string bytes = slurp(dir / "initial.png");
  REQUIRE(bytes.size() > 8);
  CHECK(bytes.compare(0, 8, std::string(kPngSignature, 8)) == 0);
  Png png(dir / "initial.png");
  REQUIRE(png.ok());
  // Window [-0.06, 2.06] x [-0.06, 1.06]: 1600 px wide, 1600 * 1.12 / 2.12 = 845 px plot + 40 px title.
  CHECK(png.width() == 1600);
  CHECK(png.height() == 845 + 40);
  const double scale = 1600 / 2.12;
  auto px = [&](Vec2 w) {
    return std::pair<int, int>(static_cast<int>((w.x + 0.06) * scale), static_cast<int>(40 + (1.06 - w.y) * scale));
  };
  const auto [ix, iy] = px({1, 0.5});
  const Rgb interior = png.pixel(ix, iy);
  CHECK(interior.r > 200);
  CHECK(interior.g < 60);
  const auto [bx, by] = px({1, 0});
  const Rgb boundary = png.pixel(bx, by);
  CHECK(boundary.b > 200);
  CHECK(boundary.r < 60);
  const auto [gx, gy] = px({0.5, 0});  // on the bottom segment, between nodes
  // The 1.5 px line straddles pixel rows; take the greenest of the rows around it.
  Rgb segment = png.pixel(gx, gy - 1);
  for (int dy = 0; dy <= 1; ++dy) {
    if (png.pixel(gx, gy + dy).g - png.pixel(gx, gy + dy).r > segment.g - segment.r) segment = png.pixel(gx, gy + dy);
  }
  CHECK(segment.g > 120);
  CHECK(segment.r < 60);
  const auto [wx, wy] = px({0.5, 0.5});  // empty interior
  CHECK(png.pixel(wx, wy).r == 255);
  CHECK(png.pixel(wx, wy).b == 255);

  const std::string svg = slurp(dir / "initial.svg");
  CHECK(svg.find("<svg") != std::string::npos);
  CHECK(svg.find("</svg>") != std::string::npos);
  fs::remove_all(dir);
}

TEST_CASE("a view window zooms in and a tall window makes a tall image", "[render]") {
  const fs::path dir = fresh_dir("view");
  NodeSet n;
  n.add({0.5, 0.5}, 0.2, NodeKind::Interior, -1);
  NodePictureOptions o;
  o.window = Box{{0.4, 0.0}, {0.6, 1.0}};
  o.long_side = 500;
  write_node_picture(dir / "initial_zoom.png", rectangle_geometry(), n, o);
  Png png(dir / "initial_zoom.png");
  REQUIRE(png.ok());
  CHECK(png.height() == 500 + 40);
  CHECK(png.width() == 160);  // 100 px by aspect ratio, raised to the minimum short side
  // The dot is in the middle of the plot and, zoomed 5x, larger than in the full view.
  CHECK(png.pixel(80, 40 + 250).r > 200);
  CHECK(png.pixel(80, 40 + 250).g < 60);
  CHECK(node_dot_radius(0.2, 500.0, false) > node_dot_radius(0.2, 100.0, false));
  CHECK(node_dot_radius(1e-9, 1.0, false) == 0.8);
  CHECK(node_dot_radius(1e9, 1.0, false) == 5.0);
  CHECK(node_dot_radius(0.2, 100.0, true) > node_dot_radius(0.2, 100.0, false));
  fs::remove_all(dir);
}

TEST_CASE("the scale bar sits in the title band beside the title, over the plot only where there is no room",
          "[render]") {
  const fs::path dir = fresh_dir("scale_bar");
  // 2 x 1 window at 800 px: 400 px per unit, a 0.2 bar of 80 px, in the band from x = 700 to 780 at y = 32.
  NodeSet n;
  n.add({0.075, 0.0625}, 0.1, NodeKind::Interior, -1);  // pixel (30, 415): where the bar used to be drawn
  NodePictureOptions o;
  o.window = Box{{0.0, 0.0}, {2.0, 1.0}};
  o.long_side = 800;
  write_node_picture(dir / "wide.png", rectangle_geometry(), n, o);
  {
    Png png(dir / "wide.png");
    REQUIRE(png.ok());
    REQUIRE(png.width() == 800);
    // The bar's line, dark, in the band.
    CHECK(png.pixel(740, 32).r < 100);
    // The node in the plot's bottom-left corner in its full colour, no white backing over it.
    const Rgb node = png.pixel(30, 415);
    CHECK(node.r > 200);
    CHECK(node.g < 60);
  }
  // 160 px wide with a title longer than the band: the bar goes on its backing in the plot's
  // bottom-left corner (a 0.05 bar of 25 px from x = 20 at y = 40 + 500 - 20).
  o.window = Box{{0.4, 0.0}, {0.6, 1.0}};
  o.long_side = 500;
  o.title = "a title longer than the picture is wide";
  write_node_picture(dir / "narrow.png", rectangle_geometry(), n, o);
  {
    Png png(dir / "narrow.png");
    REQUIRE(png.ok());
    REQUIRE(png.width() == 160);
    CHECK(png.pixel(32, 520).r < 100);
  }
  fs::remove_all(dir);
}

TEST_CASE("mesh pictures fill triangles by value and draw a colour bar", "[render]") {
  const fs::path dir = fresh_dir("mesh");
  const Mesh m = unit_square_mesh();
  const std::vector<double> values = {0.25, 1.0};
  MeshPictureOptions o;
  o.title = "square";
  o.triangle_values = &values;
  o.value_label = "quality";
  o.long_side = 400;
  write_mesh_picture(dir / "final.png", m, o);
  write_mesh_picture(dir / "final.svg", m, o);
  CHECK(entries(dir) == 2);
  Png png(dir / "final.png");
  REQUIRE(png.ok());
  CHECK(png.width() == 400 + 150);
  CHECK(png.height() == 400 + 40);
  const double scale = 400 / 1.06;
  auto px = [&](Vec2 w) {
    return std::pair<int, int>(static_cast<int>((w.x + 0.03) * scale), static_cast<int>(40 + (1.03 - w.y) * scale));
  };
  // Lower-right triangle has the minimum (ramp start), upper-left the maximum (ramp end).
  const auto [lx, ly] = px({0.8, 0.2});
  const Rgb low = png.pixel(lx, ly);
  CHECK(low.r == Approx(255 * colour_ramp(0).r).margin(3));
  CHECK(low.b == Approx(255 * colour_ramp(0).b).margin(3));
  const auto [hx, hy] = px({0.2, 0.8});
  const Rgb high = png.pixel(hx, hy);
  CHECK(high.r == Approx(255 * colour_ramp(1).r).margin(3));
  CHECK(high.g == Approx(255 * colour_ramp(1).g).margin(3));
  // The colour bar: yellow near its top, dark purple near its bottom.
  CHECK(png.pixel(400 + 45, 40 + 45).r > 200);
  CHECK(png.pixel(400 + 45, 440 - 45).b > 60);
  CHECK(png.pixel(400 + 45, 440 - 45).g < 40);
  fs::remove_all(dir);
}

TEST_CASE("a fixed value range places values on the ramp and clamps those outside it", "[render]") {
  const fs::path dir = fresh_dir("range");
  const Mesh m = unit_square_mesh();
  const std::vector<double> values = {30.0, 100.0};  // lower-right, upper-left
  MeshPictureOptions o;
  o.triangle_values = &values;
  o.value_range = std::pair<double, double>(0.0, 60.0);
  o.long_side = 400;
  write_mesh_picture(dir / "range.png", m, o);
  Png png(dir / "range.png");
  REQUIRE(png.ok());
  const double scale = 400 / 1.06;
  auto px = [&](Vec2 w) {
    return std::pair<int, int>(static_cast<int>((w.x + 0.03) * scale), static_cast<int>(40 + (1.03 - w.y) * scale));
  };
  const auto [mx, my] = px({0.8, 0.2});
  const Rgb mid = png.pixel(mx, my);  // 30 of [0, 60]: the middle of the ramp, not its start
  CHECK(mid.g == Approx(255 * colour_ramp(0.5).g).margin(3));
  CHECK(mid.r == Approx(255 * colour_ramp(0.5).r).margin(3));
  const auto [hx, hy] = px({0.2, 0.8});
  const Rgb high = png.pixel(hx, hy);  // 100 > 60: clamped to the end
  CHECK(high.r == Approx(255 * colour_ramp(1).r).margin(3));
  fs::remove_all(dir);
}

TEST_CASE("colour ramp end points and clamping", "[render]") {
  CHECK(colour_ramp(-1).r == colour_ramp(0).r);
  CHECK(colour_ramp(2).g == colour_ramp(1).g);
  CHECK(colour_ramp(0.5).g == Approx(0.471));
  CHECK(colour_ramp(NAN).r == 0.75);
}

TEST_CASE("picture errors: bad extension, bad values, missing directory", "[render]") {
  const fs::path dir = fresh_dir("errors");
  Mesh m;
  m.points = {{0, 0}, {1, 0}, {0, 1}};
  m.triangles = {{0, 1, 2}};
  CHECK_THROWS_AS(write_mesh_picture(dir / "x.jpg", m, {}), InputError);
  const std::vector<double> wrong = {1, 2};
  MeshPictureOptions o;
  o.triangle_values = &wrong;
  CHECK_THROWS_AS(write_mesh_picture(dir / "x.png", m, o), Error);
  m.triangles = {{0, 1, 3}};
  CHECK_THROWS_AS(write_mesh_picture(dir / "x.png", m, {}), Error);
  CHECK(entries(dir) == 0);
  CHECK_THROWS_AS(write_node_picture(dir / "missing" / "x.png", rectangle_geometry(), NodeSet{}, {}), InputError);
  CHECK_THROWS_AS(write_node_picture(dir / "missing" / "x.svg", rectangle_geometry(), NodeSet{}, {}), Error);
  fs::remove_all(dir);
}

TEST_CASE("mesh pictures shade triangles too small to draw instead of painting them black", "[render]") {
  const fs::path dir = fresh_dir("dense");
  // The unit square as a 300 x 300 grid of split cells (180,000 triangles): at 400 pixels a cell is
  // about 1.3 pixels wide, below the smallest edge drawn.
  const Mesh m = grid_mesh(300, [](double x, double y) { return Vec2{x, y}; });
  MeshPictureOptions o;
  o.long_side = 400;
  write_mesh_picture(dir / "dense.png", m, o);
  Png png(dir / "dense.png");
  REQUIRE(png.ok());
  // The middle of the square: the uniform grey shade (0.55), neither black edges nor white paper.
  double sum = 0;
  int count = 0;
  for (int y = 200; y < 240; ++y)
    for (int x = 180; x < 220; ++x) {
      const Rgb p = png.pixel(x, y);
      CHECK(p.r == Approx(255 * 0.55).margin(3));
      sum += p.r;
      ++count;
    }
  CHECK(sum / count == Approx(255 * 0.55).margin(2));
  // A coarse mesh keeps its edges: a pixel on the unit square's diagonal is dark.
  const Mesh coarse = unit_square_mesh();
  write_mesh_picture(dir / "coarse.png", coarse, o);
  Png c(dir / "coarse.png");
  REQUIRE(c.ok());
  const double scale = 400 / 1.06;
  const int x = static_cast<int>((0.5 + 0.03) * scale), y = static_cast<int>(40 + (1.03 - 0.5) * scale);
  double darkest = 255;
  for (int dy = -1; dy <= 1; ++dy) darkest = std::min(darkest, c.pixel(x, y + dy).r);
  CHECK(darkest < 128);
  fs::remove_all(dir);
}

TEST_CASE("a value fill too dense for its edges blends its triangles' colours, never the paper's", "[render]") {
  const fs::path dir = fresh_dir("dense_values");
  // 180,000 triangles of 1.3 px cells, the two of each cell at the ramp's two ends: where the fill
  // left seams, the white paper would show between them, off the line between the two colours.
  const Mesh m = grid_mesh(300, [](double x, double y) { return Vec2{x, y}; });
  std::vector<double> values(m.triangles.size());
  for (std::size_t t = 0; t < values.size(); ++t) values[t] = static_cast<double>(t % 2);
  MeshPictureOptions o;
  o.long_side = 400;
  o.triangle_values = &values;
  write_mesh_picture(dir / "dense.png", m, o);
  Png png(dir / "dense.png");
  REQUIRE(png.ok());
  const Rgb lo = colour_ramp(0), hi = colour_ramp(1);
  // Each pixel's distance in RGB from the segment between the two colours, and where along it it
  // lies (w = 0 at hi, 1 at lo). The paper (white) is over 150 levels off the segment.
  const double dr = 255 * (lo.r - hi.r), dg = 255 * (lo.g - hi.g), db = 255 * (lo.b - hi.b);
  const double length2 = dr * dr + dg * dg + db * db;
  double worst = 0, w_min = 1, w_max = 0;
  for (int y = 200; y < 240; ++y)
    for (int x = 180; x < 220; ++x) {
      const Rgb p = png.pixel(x, y);
      const double pr = p.r - 255 * hi.r, pg = p.g - 255 * hi.g, pb = p.b - 255 * hi.b;
      const double w = (pr * dr + pg * dg + pb * db) / length2;
      const double er = pr - w * dr, eg = pg - w * dg, eb = pb - w * db;
      worst = std::max(worst, std::sqrt(er * er + eg * eg + eb * eb));
      w_min = std::min(w_min, w);
      w_max = std::max(w_max, w);
    }
  CHECK(worst <= 8);
  CHECK(w_min >= -0.02);
  CHECK(w_max <= 1.02);
  CHECK(w_max - w_min > 0.1);  // the two colours both show
  fs::remove_all(dir);
}

TEST_CASE("a mesh too dense for its picture gets a close-up around its smallest angle", "[render]") {
  // The unit square as a 300 x 300 grid (1.3 px cells at 400 px): one node moved towards its right
  // neighbour makes the smallest angles next to it.
  const int k = 300;
  Mesh m = grid_mesh(k, [](double x, double y) { return Vec2{x, y}; });
  const int moved = 200 * (k + 1) + 100;  // the node at (100/300, 200/300)
  m.points[moved].x += 0.6 / k;
  const Box whole = padded_window(Box{{0, 0}, {1, 1}});
  const std::optional<CloseUp> close_up = dense_mesh_close_up(m, whole, 400);
  REQUIRE(close_up.has_value());
  CHECK(close_up->window.contains(m.points[moved]));
  // About kCloseUpEdges of the worst triangle's longest edge (here between 1 and 1.6 cells) across.
  CHECK(close_up->window.width() == Approx(close_up->window.height()));
  CHECK(close_up->window.width() > kCloseUpEdges * 1.0 / k);
  CHECK(close_up->window.width() < kCloseUpEdges * 1.7 / k);
  double smallest = 180;
  for (const auto& t : m.triangles)
    smallest = std::min(smallest, triangle_quality(m.points[t[0]], m.points[t[1]], m.points[t[2]]).min_angle);
  CHECK(close_up->min_angle == smallest);
  CHECK(close_up->min_angle < 30.0);

  // Drawn at the close-up's window, the edges show: dark pixels, not only the dense shade.
  const fs::path dir = fresh_dir("close_up");
  MeshPictureOptions o;
  o.long_side = 400;
  o.window = close_up->window;
  write_mesh_picture(dir / "close.png", m, o);
  Png png(dir / "close.png");
  REQUIRE(png.ok());
  // Dark: darker than the dense shade (0.55 x 255), as a 0.6 px edge makes the pixels it crosses.
  int dark = 0;
  for (int y = 40; y < png.height(); ++y)
    for (int x = 0; x < png.width(); ++x) dark += png.pixel(x, y).r < 128 ? 1 : 0;
  INFO("dark pixels " << dark);
  CHECK(dark > 400 * 40);
  fs::remove_all(dir);

  // A worst triangle on the boundary: the square moves half-way towards the mesh beside it, still
  // showing the triangle.
  Mesh edge = grid_mesh(k, [](double x, double y) { return Vec2{x, y}; });
  const int on_wall = 150;  // the node at (150/300, 0) on the bottom side
  edge.points[on_wall].x += 0.6 / k;
  const std::optional<CloseUp> wall_close_up = dense_mesh_close_up(edge, whole, 400);
  REQUIRE(wall_close_up.has_value());
  CHECK(wall_close_up->window.contains(edge.points[on_wall]));
  CHECK(wall_close_up->window.centre().y > 0.1 * wall_close_up->window.height());  // unmoved: 0.008
  CHECK(wall_close_up->window.centre().x == Approx(edge.points[on_wall].x).margin(1.0 / k));

  // The worst triangle a large one beside the dense grid (a coarse far field's): its close-up would be
  // as wide as the whole picture, so there is none.
  Mesh far = grid_mesh(k, [](double x, double y) { return Vec2{x, y}; });
  const int first = static_cast<int>(far.points.size());
  far.points.insert(far.points.end(), {{1.5, 0.0}, {2.5, 0.0}, {2.0, 0.2}});  // angles 21.8, 21.8, 136.4
  far.triangles.push_back({first, first + 1, first + 2});
  const Box far_window = padded_window(Box{{0, 0}, {2.5, 1}});
  CHECK_FALSE(dense_mesh_close_up(far, far_window, 400).has_value());

  // The whole square at 4000 px draws its edges (13 px cells), as does a coarse mesh: no close-up.
  CHECK_FALSE(dense_mesh_close_up(m, whole, 4000).has_value());
  CHECK_FALSE(dense_mesh_close_up(unit_square_mesh(), whole, 400).has_value());
  CHECK_FALSE(dense_mesh_close_up(Mesh{}, whole, 400).has_value());
}

TEST_CASE("a metric picture drawn in bands is the picture one canvas draws, pixel for pixel", "[render]") {
  const fs::path dir = fresh_dir("metric_bands");
  // Ellipses from a few pixels to a tenth of the picture, stretched and turned, so that the bands
  // cut through ellipses of every size and the polygons have from the fewest to the most sides.
  const Mesh m = grid_mesh(24, [](double x, double y) { return Vec2{x, y}; });
  std::vector<Metric> metrics(m.points.size());
  for (std::size_t i = 0; i < metrics.size(); ++i) {
    const Vec2 p = m.points[i];
    const double h1 = 0.002 + 0.1 * p.x, h2 = h1 * (1.0 + 3.0 * p.y), a = 3.0 * p.x + p.y;
    const double c = std::cos(a), s = std::sin(a), l1 = 1.0 / (h1 * h1), l2 = 1.0 / (h2 * h2);
    metrics[i] = Metric{l1 * c * c + l2 * s * s, (l1 - l2) * c * s, l1 * s * s + l2 * c * c};
  }
  MetricPictureOptions o;
  o.title = "metric bands";
  o.long_side = 500;
  o.bands = 1;
  write_metric_picture(dir / "one.png", m, metrics, o);
  for (const int bands : {2, 3, 7}) {
    o.bands = bands;
    write_metric_picture(dir / "bands.png", m, metrics, o);
    Png one(dir / "one.png"), banded(dir / "bands.png");
    REQUIRE(one.ok());
    REQUIRE(banded.ok());
    REQUIRE(banded.width() == one.width());
    REQUIRE(banded.height() == one.height());
    INFO("bands " << bands);
    CHECK(differing_pixels(one, banded) == 0);
  }
  // The ellipses are there: red pixels in the plot.
  Png one(dir / "one.png");
  int red = 0;
  for (int y = 40; y < one.height(); ++y)
    for (int x = 0; x < one.width(); ++x) {
      const Rgb p = one.pixel(x, y);
      red += p.r > 150 && p.g < 100 && p.b < 100;
    }
  CHECK(red > 2000);
}

TEST_CASE("a mesh picture drawn in bands is the picture one canvas draws, pixel for pixel", "[render]") {
  const fs::path dir = fresh_dir("bands");
  // A 120 x 120 grid of split cells warped by x -> x^3, y -> y^2: dense (shaded) towards x = 0,
  // coarse (edges drawn) towards x = 1, so that every band gets a different share of both.
  const Mesh m = grid_mesh(120, [](double x, double y) { return Vec2{x * x * x, y * y}; });
  std::vector<double> values(m.triangles.size());
  for (std::size_t t = 0; t < values.size(); ++t) values[t] = static_cast<double>(t % 97);
  for (const bool coloured : {false, true}) {
    MeshPictureOptions o;
    o.title = "bands";
    o.long_side = 500;
    if (coloured) o.triangle_values = &values;
    o.bands = 1;
    write_mesh_picture(dir / "one.png", m, o);
    for (const int bands : {2, 3, 7}) {
      o.bands = bands;
      write_mesh_picture(dir / "bands.png", m, o);
      Png one(dir / "one.png"), banded(dir / "bands.png");
      REQUIRE(one.ok());
      REQUIRE(banded.ok());
      REQUIRE(banded.width() == one.width());
      REQUIRE(banded.height() == one.height());
      const int differing = differing_pixels(one, banded);
      INFO("coloured " << coloured << ", bands " << bands);
      CHECK(differing == 0);
    }
    // The picture is not blank: the shaded part and the drawn edges are both there.
    Png one(dir / "one.png");
    int grey = 0, dark = 0;
    for (int y = 40; y < one.height(); ++y)
      for (int x = 0; x < 500; ++x) {
        const Rgb p = one.pixel(x, y);
        grey += std::abs(p.r - 255 * 0.55) < 3 && p.r == p.g;
        dark += p.r < 60 && p.g < 60 && p.b < 60;
      }
    if (!coloured) CHECK(grey > 1000);
    CHECK(dark > 1000);
  }
  // Denser than a quarter of the pixels: the shade is a PixelSplat (180,000 triangles at 400 px).
  const Mesh fine = grid_mesh(300, [](double x, double y) { return Vec2{x * x * x, y * y}; });
  MeshPictureOptions f;
  f.long_side = 400;
  f.bands = 1;
  write_mesh_picture(dir / "one.png", fine, f);
  for (const int bands : {3, 7}) {
    f.bands = bands;
    write_mesh_picture(dir / "bands.png", fine, f);
    Png one(dir / "one.png"), banded(dir / "bands.png");
    REQUIRE(one.ok());
    REQUIRE(banded.ok());
    const int differing = differing_pixels(one, banded);
    INFO("splat, bands " << bands);
    CHECK(differing == 0);
  }
  CHECK(entries(dir) == 2);  // no temporary left behind
  fs::remove_all(dir);
}

TEST_CASE("a mesh's long edges are stroked in groups whose pixel rows do not meet, as few as the rows need",
          "[render]") {
  const fs::path dir = fresh_dir("edge_strokes");
  // Long edges towards x = 1, short ones in between, edges under 2 px towards x = 0.
  const Mesh m = grid_mesh(60, [](double x, double y) { return Vec2{x * x, y}; });
  const std::vector<std::pair<int, int>> edges = unique_edges(m);
  CanvasOptions o;
  o.window = default_mesh_window(m);
  o.long_side = 600;
  const Canvas canvas(o, ImageFormat::Png, dir / "unused.png");
  const EdgeStrokes plan = plan_edge_strokes(canvas, m, edges);
  REQUIRE(!plan.ends.empty());
  CHECK(plan.ends.back() == plan.edges.size());
  const auto length = [&](const std::pair<int, int>& e) {
    return dist(canvas.to_pixel(m.points[e.first]), canvas.to_pixel(m.points[e.second]));
  };
  // Every edge once: drawn (2 px or longer) or counted as too short.
  std::vector<std::pair<int, int>> drawn = plan.edges, expected;
  std::size_t long_edges = 0;
  for (const auto& e : edges) {
    if (length(e) >= kMinEdgePixels) expected.push_back(e);
    long_edges += length(e) >= kApartEdgePixels;
  }
  std::sort(drawn.begin(), drawn.end());
  std::sort(expected.begin(), expected.end());
  CHECK(drawn == expected);
  CHECK(plan.too_short == edges.size() - expected.size());
  CHECK(plan.too_short > 0);
  CHECK(long_edges > 100);
  CHECK(expected.size() - long_edges > 100);
  // An edge's rows: those its line (0.6 px wide) touches, widened by half a pixel.
  const auto rows = [&](const std::pair<int, int>& e) {
    const double ya = canvas.to_pixel(m.points[e.first]).y, yb = canvas.to_pixel(m.points[e.second]).y;
    return std::pair<double, double>{std::floor(std::min(ya, yb) - 0.5), std::floor(std::max(ya, yb) + 0.5)};
  };
  // The short edges' strokes first (short edges only), then the long ones', within which no two
  // edges' rows meet.
  std::size_t begin = 0, shared = 0, long_strokes = 0, mixed = 0;
  bool long_seen = false;
  for (const std::size_t end : plan.ends) {
    REQUIRE(end > begin);
    const bool long_stroke = length(plan.edges[begin]) >= kApartEdgePixels;
    long_seen = long_seen || long_stroke;
    long_strokes += long_stroke;
    for (std::size_t a = begin; a < end; ++a) {
      mixed += (length(plan.edges[a]) >= kApartEdgePixels) != long_stroke;
      for (std::size_t b = a + 1; b < end && long_stroke; ++b) {
        const auto ra = rows(plan.edges[a]), rb = rows(plan.edges[b]);
        shared += !(ra.second < rb.first || rb.second < ra.first);
      }
    }
    CHECK((long_stroke || !long_seen));
    begin = end;
  }
  CHECK(shared == 0);
  CHECK(mixed == 0);
  // As many long strokes as the most long edges in one row.
  std::map<double, std::size_t> per_row;
  for (const auto& e : plan.edges) {
    if (length(e) < kApartEdgePixels) continue;
    const auto r = rows(e);
    for (double y = r.first; y <= r.second; ++y) ++per_row[y];
  }
  std::size_t most = 0;
  for (const auto& [row, count] : per_row) most = std::max(most, count);
  CHECK(long_strokes == most);
  fs::remove_all(dir);
}

TEST_CASE("a grey canvas draws the picture an RGB one draws, within a level, as a greyscale PNG", "[render]") {
  const fs::path dir = fresh_dir("grey_canvas");
  // Everything a picture of greys draws: thin and thick strokes, a filled batch with its seam
  // hairline (cut), dots, a pixel splat, the title with the scale bar on its white backing in the
  // plot (a title band too low for it), in one canvas and in bands.
  const auto draw = [](Canvas& canvas) {
    {
      FillBatch shade(canvas, Rgb{0.55, 0.55, 0.55});
      for (int k = 0; k < 40; ++k) {
        const double x = 0.05 * k;
        shade.triangle({x, 0.1}, {x + 0.06, 0.1}, {x + 0.03, 0.5});
      }
      shade.flush(true);
    }
    {
      StrokeBatch lines(canvas, colours::kBlack, 0.6, CAIRO_LINE_CAP_BUTT);
      for (int k = 0; k < 60; ++k) lines.segment({0.03 * k, 0.0}, {2.0 - 0.02 * k, 1.0});
    }
    {
      StrokeBatch thick(canvas, colours::kBlack, 2.0);
      thick.box(Box{{0.2, 0.2}, {1.8, 0.8}});
    }
    {
      DotBatch dots(canvas, Rgb{0.3, 0.3, 0.3});
      for (int k = 0; k < 30; ++k) dots.dot({0.06 * k + 0.1, 0.7}, 0.5 + 0.1 * k);
    }
    if (canvas.raster()) {
      PixelSplat splat(canvas, colours::kBlack);
      for (int k = 0; k < 400; ++k) splat.dot({1.0 + 0.001 * k, 0.3 + 0.0005 * k}, 0.7);
    }
    canvas.title("grey 0123456789");
  };
  CanvasOptions o;
  o.window = padded_window(Box{{0, 0}, {2, 1}});
  o.long_side = 400;
  o.title_height = 20;
  for (const int bands : {1, 3}) {
    INFO("bands " << bands);
    o.grey = false;
    render_picture(dir / "rgb.png", o, draw, bands);
    o.grey = true;
    render_picture(dir / "grey.png", o, draw, bands);
    Png rgb(dir / "rgb.png"), grey(dir / "grey.png");
    REQUIRE(rgb.ok());
    REQUIRE(grey.ok());
    REQUIRE(grey.width() == rgb.width());
    REQUIRE(grey.height() == rgb.height());
    const std::string bytes = slurp(dir / "grey.png");
    CHECK(bytes[25] == 0);  // IHDR's colour type: greyscale
    double most = 0;
    int inked = 0;
    for (int y = 0; y < rgb.height(); ++y)
      for (int x = 0; x < rgb.width(); ++x) {
        const Rgb a = rgb.pixel(x, y), b = grey.pixel(x, y);
        most = std::max({most, std::abs(a.r - b.r), std::abs(a.g - b.g), std::abs(a.b - b.b)});
        inked += a.r < 250;
      }
    CHECK(most <= 1);
    CHECK(inked > 5000);
  }
  fs::remove_all(dir);
}

TEST_CASE("a pixel splat covers a box's pixels and spreads a dot's area over the four pixels around it", "[render]") {
  const fs::path dir = fresh_dir("splat");
  const CanvasOptions options = plot_200();
  {
    Canvas canvas(options, ImageFormat::Png, dir / "a.png");
    REQUIRE(canvas.scale() == 1.0);
    REQUIRE(canvas.to_pixel({0, 200}).x == 0.0);
    REQUIRE(canvas.to_pixel({0, 200}).y == 0.0);
    {
      PixelSplat splat(canvas, colours::kBlack);
      splat.box(Box{{10.2, 180.5}, {12.7, 185.1}});   // pixels x 10-12, rows 14.9-19.5: 14-19
      splat.dot({50.5, 149.5}, 1 / std::sqrt(M_PI));  // area 1 at pixel (50, 50)'s centre
      splat.dot({71.0, 149.5}, 1 / std::sqrt(M_PI));  // area 1 on the line between pixels 70 and 71
      splat.dot({30.5, 149.5}, 2.0);                  // area 4pi at one pixel's centre: full, not more
    }
    for (int y = 14; y <= 19; ++y)
      for (int x = 10; x <= 12; ++x) CHECK(red_at(canvas, x, y) == 0);
    CHECK(red_at(canvas, 9, 16) == 255);
    CHECK(red_at(canvas, 13, 16) == 255);
    CHECK(red_at(canvas, 11, 13) == 255);
    CHECK(red_at(canvas, 11, 20) == 255);
    CHECK(red_at(canvas, 50, 50) == 0);
    CHECK(red_at(canvas, 51, 50) == 255);
    CHECK(red_at(canvas, 50, 49) == 255);
    CHECK(std::abs(red_at(canvas, 70, 50) - 128) <= 1);
    CHECK(std::abs(red_at(canvas, 71, 50) - 128) <= 1);
    CHECK(red_at(canvas, 72, 50) == 255);
    CHECK(red_at(canvas, 30, 50) == 0);
    CHECK(red_at(canvas, 31, 50) == 255);
  }
  {
    // A band of rows 40-69 covers only its own rows, at the picture's pixel positions.
    Canvas band(options, ImageFormat::Png, dir / "b.png", PixelRows{40, 30});
    {
      PixelSplat splat(band, colours::kBlack);
      splat.dot({50.5, 149.5}, 1 / std::sqrt(M_PI));  // row 50: in the band
      splat.dot({50.5, 189.5}, 1 / std::sqrt(M_PI));  // row 10: another band's
      splat.box(Box{{20, 120}, {21, 170}});           // rows 30-80: the band's part only
    }
    CHECK(red_at(band, 50, 50) == 0);
    CHECK(red_at(band, 50, 40) == 255);
    for (int y = 40; y < 70; ++y) CHECK(red_at(band, 20, y) == 0);
  }
  // Dense enough: more items than a quarter of the plot's 200 x 200 pixels, and a PNG.
  Canvas png(options, ImageFormat::Png, dir / "c.png");
  CHECK_FALSE(splat_worthwhile(png, 10000));
  CHECK(splat_worthwhile(png, 10001));
  Canvas svg(options, ImageFormat::Svg, dir / "d.svg");
  CHECK_FALSE(splat_worthwhile(svg, 1000000));
  fs::remove_all(dir);
}

TEST_CASE("a node picture of more nodes than a quarter of its pixels shades by the nodes' density", "[render]") {
  const fs::path dir = fresh_dir("dense_nodes");
  // Interior nodes 0.005 units (0.94 px at 400 px) apart on the rectangle [0, 2] x [0, 1], only every
  // other column and row in its left half (1.88 px apart). Their dots have the smallest radius,
  // 0.8 px (area 2.01 px^2): the right half is covered, the left one by 2.01 / 1.88^2 = 57 %.
  const Geometry g = rectangle_geometry();
  NodeSet n;
  const double step = 2.0 / 400;
  for (int j = 0; j < 200; ++j)
    for (int i = 0; i < 400; ++i) {
      if (i < 200 && (i % 2 != 0 || j % 2 != 0)) continue;
      n.add({(i + 0.5) * step, (j + 0.5) * step}, 1e-4, NodeKind::Interior, -1);
    }
  NodePictureOptions o;
  o.long_side = 400;
  write_node_picture(dir / "n.png", g, n, o);
  Png png(dir / "n.png");
  REQUIRE(png.ok());
  // The picture's transform, from a canvas of the same layout.
  CanvasOptions layout;
  layout.window = padded_window(g.extents);
  layout.long_side = 400;
  Canvas same(layout, ImageFormat::Png, dir / "layout.png");
  REQUIRE(splat_worthwhile(same, n.size()));
  const double px = 1 / same.scale();
  // The mean green channel (255 on paper, 0 under a red dot) well inside a part of the rectangle.
  const auto mean_green = [&](double x0, double x1) {
    double sum = 0;
    int count = 0;
    for (double wy = 0.3; wy <= 0.7; wy += px)
      for (double wx = x0; wx <= x1; wx += px) {
        const Vec2 p = same.to_pixel({wx, wy});
        sum += png.pixel(static_cast<int>(p.x), static_cast<int>(p.y)).g;
        ++count;
      }
    return sum / count;
  };
  const double spacing_px = 2 * step * same.scale();
  CHECK(mean_green(1.3, 1.7) < 10);
  CHECK(mean_green(0.3, 0.7) == Approx(255 * (1 - M_PI * 0.8 * 0.8 / (spacing_px * spacing_px))).margin(20));
  fs::remove_all(dir);
}

TEST_CASE("a mesh denser than a quarter of its pixels is shaded without seams, the same in bands", "[render]") {
  const fs::path dir = fresh_dir("sharp_shade");
  // A 300 x 300 grid of split cells (180,000 triangles, a PixelSplat's shade): at 400 pixels a cell is
  // about 1.3 pixels wide and its diagonal under 2, so the whole square is shaded and no edge drawn.
  const Mesh m = grid_mesh(300, [](double x, double y) { return Vec2{x, y}; });
  REQUIRE(m.triangles.size() > 0.25 * 400 * 400);
  MeshPictureOptions o;
  o.long_side = 400;
  o.bands = 1;
  write_mesh_picture(dir / "one.png", m, o);
  Png one(dir / "one.png");
  REQUIRE(one.ok());
  // Inside the square (above the scale bar at its bottom left) every pixel is the shade itself: no
  // lighter pixels where the triangles meet.
  const double scale = 400 / 1.06;
  const int x0 = static_cast<int>((0.03 + 0.05) * scale), x1 = static_cast<int>((0.03 + 0.95) * scale);
  const int y0 = static_cast<int>(40 + (1.03 - 0.95) * scale), y1 = static_cast<int>(40 + (1.03 - 0.2) * scale);
  const double shade = std::round(255 * 0.55);
  int off = 0;
  for (int y = y0; y < y1; ++y)
    for (int x = x0; x < x1; ++x) {
      const Rgb p = one.pixel(x, y);
      off += p.r != shade || p.g != shade || p.b != shade;
    }
  CHECK(off == 0);
  for (const int bands : {2, 5}) {
    o.bands = bands;
    write_mesh_picture(dir / "bands.png", m, o);
    Png banded(dir / "bands.png");
    REQUIRE(banded.ok());
    REQUIRE(banded.width() == one.width());
    REQUIRE(banded.height() == one.height());
    const int differing = differing_pixels(one, banded);
    INFO("bands " << bands);
    CHECK(differing == 0);
  }
  fs::remove_all(dir);
}

TEST_CASE("a fill batch told it holds up to 2^18 triangles fills them at once, without the seams' hairline",
          "[render]") {
  const fs::path dir = fresh_dir("single_fill");
  const CanvasOptions options = plot_200();
  // The square [50, 150]^2 (pixels 50-149) as 72,200 triangles: more than one batch of 65,536.
  const int k = 190;
  const auto at = [&](int i, int j) { return Vec2{50.0 + 100.0 * i / k, 50.0 + 100.0 * j / k}; };
  const std::size_t items = 2 * static_cast<std::size_t>(k) * k;
  REQUIRE(items > 65536);
  REQUIRE(items <= FillBatch::kSingleFillItems);
  Canvas canvas(options, ImageFormat::Png, dir / "a.png");
  REQUIRE(canvas.scale() == 1.0);
  {
    FillBatch fill(canvas, colours::kBlack, items);
    for (int j = 0; j < k; ++j)
      for (int i = 0; i < k; ++i) {
        fill.triangle(at(i, j), at(i + 1, j), at(i + 1, j + 1));
        fill.triangle(at(i, j), at(i + 1, j + 1), at(i, j + 1));
      }
  }
  // Their union, filled once: full inside, nothing beyond the square's edges (a hairline stroke of
  // the batches' outlines would put a quarter pixel of ink on the pixels around it).
  for (const int y : {50, 100, 149}) {
    CHECK(red_at(canvas, 50, y) == 0);
    CHECK(red_at(canvas, 100, y) == 0);
    CHECK(red_at(canvas, 149, y) == 0);
    CHECK(red_at(canvas, 49, y) == 255);
    CHECK(red_at(canvas, 150, y) == 255);
  }
  for (const int x : {50, 100, 149}) {
    CHECK(red_at(canvas, x, 49) == 255);
    CHECK(red_at(canvas, x, 150) == 255);
  }
  // The same in a mesh picture whose shade is one such fill: drawn in bands, it is the picture one
  // canvas draws (every band counts the same items).
  Mesh m = grid_mesh(k, [](double x, double y) { return Vec2{0.1 * x, 0.1 * y}; });
  MeshPictureOptions o;
  o.window = Box{{-0.5, -0.5}, {0.6, 0.6}};
  o.long_side = 1000;  // a quarter of its pixels is more than the triangles: no pixel splat
  o.bands = 1;
  write_mesh_picture(dir / "one.png", m, o);
  o.bands = 4;
  write_mesh_picture(dir / "bands.png", m, o);
  Png one(dir / "one.png"), banded(dir / "bands.png");
  REQUIRE(one.ok());
  REQUIRE(banded.ok());
  CHECK(differing_pixels(one, banded) == 0);
  fs::remove_all(dir);
}

TEST_CASE("a banded picture with colour in some bands only is one RGB PNG, pixel for pixel one canvas' picture",
          "[render]") {
  const fs::path dir = fresh_dir("mixed_bands");
  CanvasOptions layout;
  layout.window = Box{{0, 0}, {1, 1}};
  layout.long_side = 300;
  // Black lines everywhere (grey bands), one red square in the bottom quarter only.
  const auto draw = [](Canvas& canvas) {
    StrokeBatch lines(canvas, colours::kBlack, 0.6);
    for (int k = 0; k <= 20; ++k) {
      const double t = k / 20.0;
      lines.segment({t, 0}, {1 - t, 1});
    }
    lines.flush();
    FillBatch red(canvas, colours::kInteriorNode);
    red.triangle({0.4, 0.05}, {0.6, 0.05}, {0.6, 0.2});
    red.triangle({0.4, 0.05}, {0.6, 0.2}, {0.4, 0.2});
  };
  render_picture(dir / "one.png", layout, draw, 1);
  render_picture(dir / "bands.png", layout, draw, 4);
  for (const char* name : {"one.png", "bands.png"}) {
    const std::string bytes = slurp(dir / name);
    REQUIRE(bytes.size() > 26);
    INFO(name);
    CHECK(bytes[25] == 2);  // IHDR's colour type: RGB
  }
  Png one(dir / "one.png"), banded(dir / "bands.png");
  REQUIRE(one.ok());
  REQUIRE(banded.ok());
  CHECK(differing_pixels(one, banded) == 0);
  const Rgb p = banded.pixel(150, 40 + 300 - 37);  // inside the red square
  CHECK(p.r > 200);
  CHECK(p.g < 50);
  fs::remove_all(dir);
}

TEST_CASE("a stroke batch with butt ends stops at the segment's ends, a default batch after it has round ends",
          "[render]") {
  const fs::path dir = fresh_dir("butt_ends");
  CanvasOptions layout;
  layout.window = Box{{0, 0}, {1, 1}};
  layout.long_side = 400;  // 400 px a unit; pixel rows start 40 px down (the title band)
  // Two horizontal 0.6 px lines on pixel rows 40 + 199 and 40 + 99, from x = 100 px to 300 px (pixel
  // edges): the first with butt ends, the second in a batch with the default (round) ends after it.
  render_picture(dir / "ends.png", layout, [&](Canvas& c) {
    StrokeBatch(c, colours::kBlack, 0.6, CAIRO_LINE_CAP_BUTT).segment({0.25, 0.50125}, {0.75, 0.50125});
    StrokeBatch(c, colours::kBlack, 0.6).segment({0.25, 0.75125}, {0.75, 0.75125});
  });
  Png png(dir / "ends.png");
  REQUIRE(png.ok());
  // Butt: the pixels beside the ends are white, the line's own pixels 0.6 covered.
  CHECK(png.pixel(99, 40 + 199).r == 255);
  CHECK(png.pixel(300, 40 + 199).r == 255);
  CHECK(png.pixel(100, 40 + 199).r == Approx(255 * 0.4).margin(2));
  CHECK(png.pixel(299, 40 + 199).r == Approx(255 * 0.4).margin(2));
  // Round: half a disc of 0.3 px beyond each end (0.14 of a pixel).
  CHECK(png.pixel(99, 40 + 99).r < 240);
  CHECK(png.pixel(300, 40 + 99).r < 240);
  fs::remove_all(dir);
}

TEST_CASE("a dot batch draws the dots of its pen radius with cairo's pen as its arcs draw them", "[render]") {
  const fs::path dir = fresh_dir("pen_dots");
  // 200 dots of 0.8 px at every quarter-pixel offset, well apart, and 50 of 2 px among them: drawn
  // as arcs, and with a pen radius of 0.8.
  const auto draw = [](double pen_radius) {
    return [pen_radius](Canvas& canvas) {
      DotBatch dots(canvas, colours::kInteriorNode, pen_radius);
      for (int k = 0; k < 200; ++k) {
        const double x = 0.05 + 0.0731 * (k % 25) + 0.0011 * (k % 4), y = 0.05 + 0.11 * (k / 25) + 0.0013 * (k % 3);
        dots.dot({x, y}, 0.8);
        if (k % 4 == 0) dots.dot({x + 0.03, y + 0.05}, 2.0);
      }
    };
  };
  CanvasOptions o;
  o.window = Box{{0, 0}, {2, 1}};
  o.long_side = 400;
  render_picture(dir / "arcs.png", o, draw(0));
  render_picture(dir / "pen.png", o, draw(0.8));
  Png arcs(dir / "arcs.png"), pen(dir / "pen.png");
  REQUIRE(arcs.ok());
  REQUIRE(pen.ok());
  double ink_arcs = 0, ink_pen = 0, most = 0;
  for (int y = 0; y < arcs.height(); ++y)
    for (int x = 0; x < arcs.width(); ++x) {
      const Rgb a = arcs.pixel(x, y), b = pen.pixel(x, y);
      ink_arcs += (255 - a.g) / 255.0;
      ink_pen += (255 - b.g) / 255.0;
      most = std::max(most, std::abs(a.g - b.g));
    }
  // The same area (200 pi 0.8^2 + 50 pi 2^2 = 1,030 px), each pixel within a fifth of full ink.
  CHECK(ink_arcs == Approx(200 * M_PI * 0.64 + 50 * M_PI * 4).epsilon(0.05));
  CHECK(ink_pen == Approx(ink_arcs).epsilon(0.03));
  CHECK(most <= 51);
  fs::remove_all(dir);
}

TEST_CASE("a node dot covers its circle's area", "[render]") {
  const fs::path dir = fresh_dir("small_dots");
  const Geometry g = rectangle_geometry();
  const double scale = 1600 / 2.12;  // the node picture's pixels per unit (see the first test)
  // Each node alone in the middle of the rectangle; the one of spacing for 0.5 px is clamped to the
  // smallest dot, drawn with cairo's pen.
  for (const double asked : {0.5, 0.9, 1.1, 1.6, 3.0}) {
    const double radius = std::max(asked, kMinNodeDot);
    NodeSet n;
    n.add({0.9, 0.4}, asked / (0.12 * scale), NodeKind::Interior, -1);
    REQUIRE(node_dot_radius(n.q[0], scale, false) == Approx(radius));
    write_node_picture(dir / "dot.png", g, n, NodePictureOptions{});
    Png png(dir / "dot.png");
    REQUIRE(png.ok());
    // The dot's coverage summed over its pixels: the green channel falls from 255 (paper) to 0.
    const int cx = static_cast<int>((0.9 + 0.06) * scale), cy = static_cast<int>(40 + (1.06 - 0.4) * scale);
    double covered = 0;
    for (int y = cy - 6; y <= cy + 6; ++y)
      for (int x = cx - 6; x <= cx + 6; ++x) covered += (255.0 - png.pixel(x, y).g) / 255.0;
    INFO("radius " << radius);
    CHECK(covered == Approx(M_PI * radius * radius).epsilon(0.1));
  }
  fs::remove_all(dir);
}
