// The spacing picture: a raster of log q over the domain (sampled from the background quadtree in
// parallel), the boundary, and a colour bar with logarithmic ticks.
#include "render/spacing_picture.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include <fmt/format.h>

#include "core/parallel.hpp"
#include "render/canvas.hpp"
#include "render/mesh_picture.hpp"

namespace pdmesh {

namespace {

constexpr int kSpacingBarBand = 170;

// Ticks at 1, 2 and 5 times powers of ten inside [lo, hi]; decades only when those are too many.
std::vector<double> log_ticks(double lo, double hi) {
  std::vector<double> ticks;
  for (const bool decades_only : {false, true}) {
    ticks.clear();
    for (double p = std::pow(10.0, std::floor(std::log10(lo))); p <= hi * 1.000001; p *= 10.0)
      for (const double m : {1.0, 2.0, 5.0}) {
        if (decades_only && m != 1.0) continue;
        const double t = m * p;
        if (t >= lo * 0.999999 && t <= hi * 1.000001) ticks.push_back(t);
      }
    if (ticks.size() <= 12) break;
  }
  return ticks;
}

void draw_log_colour_bar(Canvas& canvas, double lo, double hi) {
  const ColourBarBox b = draw_colour_ramp_bar(canvas);
  cairo_t* cr = canvas.context();
  const double span = hi > lo ? std::log(hi / lo) : 1.0;
  for (const double t : log_ticks(lo, hi)) {
    const double y = b.top + b.height * (1.0 - (hi > lo ? std::log(t / lo) / span : 0.5));
    cairo_move_to(cr, b.x + b.width, y);
    cairo_line_to(cr, b.x + b.width + 5, y);
    cairo_stroke(cr);
    canvas.text(b.x + b.width + 8, y + 5, fmt::format("{:g}", t), 13, colours::kBlack);
  }
  canvas.text(b.x - 10, b.top - 24, "q (log scale)", 14, colours::kBlack);
  canvas.text(b.x - 10, b.top - 8, fmt::format("{:.3g} .. {:.3g}", lo, hi), 12, colours::kBlack);
}

}  // namespace

void write_spacing_picture(const std::filesystem::path& path, const GeometryTree& tree, const BackgroundSpacing& field,
                           const SpacingPictureOptions& options) {
  const Geometry& g = tree.geometry();
  CanvasOptions layout;
  layout.window = options.window ? *options.window : padded_window(g.extents);
  layout.long_side = options.long_side;
  layout.side_width = kSpacingBarBand;
  render_picture(path, layout, [&](Canvas& canvas) {
    // The pixels the window maps to; each is sampled at its centre.
    const Box& w = canvas.window();
    const Vec2 p0 = canvas.to_pixel({w.lo.x, w.hi.y}), p1 = canvas.to_pixel({w.hi.x, w.lo.y});
    const int x0 = static_cast<int>(std::floor(p0.x)), y0 = static_cast<int>(std::floor(p0.y));
    const int nx = std::max(1, static_cast<int>(std::ceil(p1.x)) - x0),
              ny = std::max(1, static_cast<int>(std::ceil(p1.y)) - y0);
    const double scale = canvas.scale();
    std::vector<double> q(static_cast<std::size_t>(nx) * static_cast<std::size_t>(ny), NAN);
    parallel_for(
        static_cast<std::size_t>(ny),
        [&](std::size_t row) {
          for (int col = 0; col < nx; ++col) {
            const Vec2 p{w.lo.x + (x0 + col + 0.5 - p0.x) / scale,
                         w.hi.y - (y0 + static_cast<double>(row) + 0.5 - p0.y) / scale};
            const int tag = field.tag_at(p);
            if (tag == kTagOutside || (tag == kTagBoundary && !tree.inside(p))) continue;
            q[row * static_cast<std::size_t>(nx) + static_cast<std::size_t>(col)] = options.value_scale * field.at(p);
          }
        },
        16);
    double lo = INFINITY, hi = 0.0;
    for (const double v : q)
      if (std::isfinite(v) && v > 0.0) {
        lo = std::min(lo, v);
        hi = std::max(hi, v);
      }
    if (!(hi > 0.0)) lo = hi = 1.0;
    cairo_surface_t* image = cairo_image_surface_create(CAIRO_FORMAT_ARGB32, nx, ny);
    cairo_surface_flush(image);
    unsigned char* data = cairo_image_surface_get_data(image);
    const int stride = cairo_image_surface_get_stride(image);
    const double span = hi > lo ? std::log(hi / lo) : 1.0;
    for (int row = 0; row < ny; ++row) {
      auto* px = reinterpret_cast<std::uint32_t*>(data + static_cast<std::ptrdiff_t>(row) * stride);
      for (int col = 0; col < nx; ++col) {
        const double v =
            q[static_cast<std::size_t>(row) * static_cast<std::size_t>(nx) + static_cast<std::size_t>(col)];
        if (!std::isfinite(v)) {
          px[col] = 0xffffffffu;  // outside the domain: white
          continue;
        }
        const Rgb c = colour_ramp(hi > lo ? std::log(v / lo) / span : 0.5);
        auto byte = [](double f) { return static_cast<std::uint32_t>(std::lround(std::clamp(f, 0.0, 1.0) * 255.0)); };
        px[col] = 0xff000000u | (byte(c.r) << 16) | (byte(c.g) << 8) | byte(c.b);
      }
    }
    cairo_surface_mark_dirty(image);
    cairo_t* cr = canvas.context();
    cairo_set_source_surface(cr, image, x0, y0);
    cairo_paint(cr);
    cairo_surface_destroy(image);
    for (const Segment& s : g.segments) canvas.line(s.a, s.b, colours::kBlack, 1.2);
    canvas.title(fmt::format("{}   q from {:.3g} to {:.3g}", options.title, lo, hi));
    draw_log_colour_bar(canvas, lo, hi);
  });
}

}  // namespace pdmesh
