// LineMask: see line_mask.hpp.
#include "render/line_mask.hpp"

#include <algorithm>
#include <cmath>

#include "core/errors.hpp"

namespace pdmesh {

LineMask::LineMask(Canvas& canvas, Rgb colour, double width_px)
    : canvas_(canvas), colour_(colour), half_width_(static_cast<float>(0.5 * width_px)) {
  if (!canvas.raster()) throw Error("LineMask: a PNG canvas only");
  if (!(width_px > 0 && std::isfinite(width_px))) throw Error("LineMask: a line width above 0");
  width_ = canvas.width();
  first_row_ = canvas.first_row();
  rows_ = std::max(canvas.end_row() - first_row_, 1);
  stride_ = cairo_format_stride_for_width(CAIRO_FORMAT_A8, width_);
  alpha_.assign(static_cast<std::size_t>(stride_) * static_cast<std::size_t>(rows_), 0);
}

void LineMask::cover(int x, int y, float coverage) {
  const int row = y - first_row_;
  if (x < 0 || x >= width_ || row < 0 || row >= rows_) return;
  unsigned char& m =
      alpha_[static_cast<std::size_t>(row) * static_cast<std::size_t>(stride_) + static_cast<std::size_t>(x)];
  const float before = m / 255.0f;
  const float after = before + std::min(coverage, 1.0f) * (1.0f - before);
  m = static_cast<unsigned char>(std::lround(255.0f * after));
  any_ = true;
}

namespace {

// The share of a pixel (a unit square) on one side of a line: the pixel's area projected onto a unit
// direction (ux, uy) is the sum of two uniform spreads of widths a = |ux| and b = |uy| (a trapezoid
// over [-(a + b)/2, (a + b)/2]); its cumulative share below s. The same for the line's normal and its
// direction (a and b swap).
struct Footprint {
  double wide, narrow;  // max(a, b), min(a, b); wide >= 1/sqrt(2)
  double below(double s) const {
    const double t = s + 0.5 * (wide + narrow);  // from the footprint's lower end
    if (t <= 0) return 0.0;
    if (t >= wide + narrow) return 1.0;
    if (narrow < 1e-9) return t / wide;
    if (t < narrow) return t * t / (2 * wide * narrow);
    if (t <= wide) return (t - 0.5 * narrow) / wide;
    const double r = wide + narrow - t;
    return 1.0 - r * r / (2 * wide * narrow);
  }
};

}  // namespace

void LineMask::segment(Vec2 wa, Vec2 wb) {
  const Vec2 a = canvas_.to_pixel(wa), b = canvas_.to_pixel(wb);
  if (!(std::isfinite(a.x) && std::isfinite(a.y) && std::isfinite(b.x) && std::isfinite(b.y))) return;
  // A pixel's coverage: the share of it within the line's half width h of the line (across), times
  // the share within the segment's ends (along), each lengthened by pi h / 4 so that the line's area
  // is that of the segment with round ends. Exact for a line along the pixel grid, away from its ends.
  const double h = half_width_;
  const double length = dist(a, b);
  const Vec2 t = length > 0 ? (b - a) * (1.0 / length) : Vec2{1, 0};
  const Vec2 n{-t.y, t.x};
  const Footprint pixel{std::max(std::abs(t.x), std::abs(t.y)), std::min(std::abs(t.x), std::abs(t.y))};
  const double end_lo = -0.25 * M_PI * h, end_hi = length + 0.25 * M_PI * h;
  // Pixel centres within `reach` of the line (across) and of its lengthened ends (along) can be covered.
  const double reach = h + 0.75;
  // Along the major axis (u) one pixel at a time, across it (v) the few pixels the line reaches.
  const bool steep = std::abs(b.y - a.y) > std::abs(b.x - a.x);
  const double au = steep ? a.y : a.x, av = steep ? a.x : a.y;
  const double bu = steep ? b.y : b.x, bv = steep ? b.x : b.y;
  const double du = bu - au;
  const double slope = du != 0 ? (bv - av) / du : 0.0;
  // The reach measured along v (over the line's cosine to the u axis).
  const double across = reach * std::sqrt(1.0 + slope * slope);
  const double extra = reach + 0.25 * M_PI * h;  // how far beyond the ends along u
  // The canvas' extent along u and v (picture pixels): items far outside it cost nothing.
  const double u_lo = steep ? first_row_ : 0.0, u_end = steep ? first_row_ + rows_ : width_;
  const double v_lo = steep ? 0.0 : first_row_, v_end = steep ? width_ : first_row_ + rows_;
  const double u_first = std::max(std::floor(std::min(au, bu) - extra), u_lo);
  const double u_last = std::min(std::floor(std::max(au, bu) + extra), u_end - 1);
  for (double iu = u_first; iu <= u_last; iu += 1.0) {
    const double uc = iu + 0.5;
    const double v_line = av + (uc - au) * slope;  // the (unbounded) line's v at this column
    const double v_first = std::max(std::floor(v_line - across), v_lo);
    const double v_last = std::min(std::floor(v_line + across), v_end - 1);
    for (double iv = v_first; iv <= v_last; iv += 1.0) {
      const double vc = iv + 0.5;
      const Vec2 c = steep ? Vec2{vc, uc} : Vec2{uc, vc};
      const Vec2 e = c - a;
      const double along = e.x * t.x + e.y * t.y;
      const double off = e.x * n.x + e.y * n.y;
      const double share_along = pixel.below(end_hi - along) - pixel.below(end_lo - along);
      if (share_along <= 0) continue;
      const double share_across = pixel.below(off + h) - pixel.below(off - h);
      if (share_across <= 0) continue;
      const int iu_int = static_cast<int>(iu), iv_int = static_cast<int>(iv);
      const auto coverage = static_cast<float>(share_along * share_across);
      if (steep)
        cover(iv_int, iu_int, coverage);
      else
        cover(iu_int, iv_int, coverage);
    }
  }
}

void LineMask::paint() {
  if (!any_) return;
  any_ = false;
  cairo_surface_t* mask = cairo_image_surface_create_for_data(alpha_.data(), CAIRO_FORMAT_A8, width_, rows_, stride_);
  cairo_t* cr = canvas_.context();
  cairo_set_source_rgb(cr, colour_.r, colour_.g, colour_.b);
  // The context is translated up by the canvas' first row: the mask's row 0 is that row.
  cairo_mask_surface(cr, mask, 0, first_row_);
  cairo_surface_destroy(mask);
  std::fill(alpha_.begin(), alpha_.end(), 0);
  canvas_.check_drawn();
}

}  // namespace pdmesh
