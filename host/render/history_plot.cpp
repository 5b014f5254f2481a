// The history plot (thesis fig. 6.1): average |F| (red) and average kinetic energy (blue) against
// the iteration on a logarithmic y axis, drawn with cairo; population events that changed the node
// set are green ticks along the bottom, longer for more nodes inserted or removed.
#include "render/history_plot.hpp"

#include <algorithm>
#include <cmath>

#include <cairo.h>
#include <fmt/format.h>

#include "core/atomic_file.hpp"
#include "core/errors.hpp"
#include "render/png_file.hpp"

namespace pdmesh {
namespace {

constexpr int kWidth = 900, kHeight = 560;
constexpr double kLeft = 90, kRight = 20, kTop = 40, kBottom = 60;
constexpr double kPlotRight = kWidth - kRight, kPlotBottom = kHeight - kBottom;

// A "nice" tick step (1, 2 or 5 times a power of ten) giving about `target` ticks over `span`.
double nice_step(double span, int target) {
  const double raw = span / target;
  const double p = std::pow(10.0, std::floor(std::log10(raw)));
  for (double m : {1.0, 2.0, 5.0})
    if (m * p >= raw) return m * p;
  return 10.0 * p;
}

void text(cairo_t* cr, double x, double y, const std::string& s, double align_x, double align_y) {
  cairo_text_extents_t e;
  cairo_text_extents(cr, s.c_str(), &e);
  cairo_move_to(cr, x - align_x * e.width - e.x_bearing, y - align_y * e.height - e.y_bearing);
  cairo_show_text(cr, s.c_str());
}

struct Frame {
  double x0, x1;  // iteration range
  double d0, d1;  // decades: log10 range of y
  double px(double it) const { return kLeft + (it - x0) / (x1 - x0) * (kWidth - kLeft - kRight); }
  double py(double v) const { return kTop + (d1 - std::log10(v)) / (d1 - d0) * (kHeight - kTop - kBottom); }
};

void draw_series(cairo_t* cr, const Frame& f, const std::vector<HistoryRow>& rows, double HistoryRow::*value) {
  bool pen_down = false;
  for (const HistoryRow& r : rows) {
    const double v = r.*value;
    if (!(v > 0.0) || !std::isfinite(v)) {  // log scale: zero or bad values break the line
      pen_down = false;
      continue;
    }
    if (pen_down)
      cairo_line_to(cr, f.px(r.iteration), f.py(v));
    else
      cairo_move_to(cr, f.px(r.iteration), f.py(v));
    pen_down = true;
  }
  cairo_stroke(cr);
}

// The frame of the plot: iterations 1 .. the last (at least 2) and the decades of the positive values.
Frame frame_of(const std::vector<HistoryRow>& rows) {
  double lo = HUGE_VAL, hi = 0.0;
  for (const HistoryRow& r : rows)
    for (double v : {r.average_force, r.average_kinetic})
      if (v > 0.0 && std::isfinite(v)) lo = std::min(lo, v), hi = std::max(hi, v);
  if (!(hi > 0.0)) lo = 0.1, hi = 10.0;
  Frame f{1.0, std::max(2.0, rows.empty() ? 2.0 : static_cast<double>(rows.back().iteration)),
          std::floor(std::log10(lo)), std::ceil(std::log10(hi))};
  if (f.d1 <= f.d0) f.d1 = f.d0 + 1.0;
  return f;
}

// The y grid and ticks at every decade (labels 1e-3 ...), with minor ticks when there are few decades.
void draw_y_axis(cairo_t* cr, const Frame& f) {
  const int decades = static_cast<int>(f.d1 - f.d0);
  for (int d = static_cast<int>(f.d0); d <= static_cast<int>(f.d1); ++d) {
    const double y = f.py(std::pow(10.0, d));
    cairo_set_source_rgb(cr, 0.88, 0.88, 0.88);
    cairo_move_to(cr, kLeft, y);
    cairo_line_to(cr, kPlotRight, y);
    cairo_stroke(cr);
    cairo_set_source_rgb(cr, 0, 0, 0);
    cairo_move_to(cr, kLeft - 6, y);
    cairo_line_to(cr, kLeft, y);
    cairo_stroke(cr);
    text(cr, kLeft - 9, y, fmt::format("1e{}", d), 1.0, 0.5);
    if (decades <= 10 && d < static_cast<int>(f.d1)) {
      for (int m = 2; m <= 9; ++m) {
        const double ym = f.py(m * std::pow(10.0, d));
        cairo_move_to(cr, kLeft - 3, ym);
        cairo_line_to(cr, kLeft, ym);
      }
      cairo_stroke(cr);
    }
  }
}

// The x grid and ticks at nice steps.
void draw_x_axis(cairo_t* cr, const Frame& f) {
  const double step = nice_step(f.x1 - f.x0, 8);
  for (double it = std::ceil(f.x0 / step) * step; it <= f.x1 + 1e-9; it += step) {
    const double x = f.px(it);
    cairo_set_source_rgb(cr, 0.88, 0.88, 0.88);
    cairo_move_to(cr, x, kTop);
    cairo_line_to(cr, x, kPlotBottom);
    cairo_stroke(cr);
    cairo_set_source_rgb(cr, 0, 0, 0);
    cairo_move_to(cr, x, kPlotBottom);
    cairo_line_to(cr, x, kPlotBottom + 6);
    cairo_stroke(cr);
    text(cr, x, kPlotBottom + 9, fmt::format("{:g}", it), 0.5, 0.0);
  }
}

// The two series and the population events' ticks, clipped to the plot area. Returns whether there
// were events (the legend then names them).
bool draw_data(cairo_t* cr, const Frame& f, const std::vector<HistoryRow>& rows) {
  cairo_save(cr);
  cairo_rectangle(cr, kLeft, kTop, kPlotRight - kLeft, kPlotBottom - kTop);
  cairo_clip(cr);
  cairo_set_line_width(cr, 1.5);
  cairo_set_source_rgb(cr, 0.85, 0.1, 0.1);
  draw_series(cr, f, rows, &HistoryRow::average_force);
  cairo_set_source_rgb(cr, 0.1, 0.2, 0.85);
  draw_series(cr, f, rows, &HistoryRow::average_kinetic);
  bool events = false;
  cairo_set_source_rgb(cr, 0.1, 0.6, 0.2);
  for (const HistoryRow& r : rows) {
    const std::size_t changed = r.inserted + r.removed;
    if (changed == 0) continue;
    events = true;
    // 6 px for one node, 6 px more per factor of 10.
    const double length = 6.0 * (1.0 + std::log10(static_cast<double>(changed)));
    cairo_move_to(cr, f.px(r.iteration), kPlotBottom);
    cairo_line_to(cr, f.px(r.iteration), kPlotBottom - length);
  }
  cairo_stroke(cr);
  cairo_restore(cr);
  return events;
}

// The axis labels and the title.
void draw_labels(cairo_t* cr, const std::string& title) {
  cairo_set_source_rgb(cr, 0, 0, 0);
  cairo_set_font_size(cr, 14);
  text(cr, 0.5 * (kLeft + kPlotRight), kHeight - 8, "iteration", 0.5, 1.0);
  cairo_save(cr);
  cairo_translate(cr, 20, 0.5 * (kTop + kPlotBottom));
  cairo_rotate(cr, -M_PI / 2);
  text(cr, 0, 0, "average per moving node (log scale)", 0.5, 0.5);
  cairo_restore(cr);
  cairo_set_font_size(cr, 15);
  text(cr, 0.5 * (kLeft + kPlotRight), 12, title, 0.5, 0.0);
}

// The legend at the top right: the two series, and the events when there were any.
void draw_legend(cairo_t* cr, bool events) {
  cairo_set_font_size(cr, 12);
  const double lx = kPlotRight - 210, ly = kTop + 14;
  cairo_set_line_width(cr, 2.0);
  cairo_set_source_rgb(cr, 0.85, 0.1, 0.1);
  cairo_move_to(cr, lx, ly);
  cairo_line_to(cr, lx + 24, ly);
  cairo_stroke(cr);
  cairo_set_source_rgb(cr, 0.1, 0.2, 0.85);
  cairo_move_to(cr, lx, ly + 18);
  cairo_line_to(cr, lx + 24, ly + 18);
  cairo_stroke(cr);
  cairo_set_source_rgb(cr, 0, 0, 0);
  text(cr, lx + 30, ly, "average |F|", 0.0, 0.5);
  text(cr, lx + 30, ly + 18, "average kinetic energy", 0.0, 0.5);
  if (events) {
    cairo_set_source_rgb(cr, 0.1, 0.6, 0.2);
    cairo_move_to(cr, lx + 12, ly + 42);
    cairo_line_to(cr, lx + 12, ly + 30);
    cairo_stroke(cr);
    cairo_set_source_rgb(cr, 0, 0, 0);
    text(cr, lx + 30, ly + 36, "nodes inserted/removed", 0.0, 0.5);
  }
}

void draw(cairo_t* cr, const std::vector<HistoryRow>& rows, const std::string& title) {
  const Frame f = frame_of(rows);
  cairo_set_source_rgb(cr, 1, 1, 1);
  cairo_paint(cr);
  cairo_select_font_face(cr, "sans-serif", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
  cairo_set_line_width(cr, 1.0);
  cairo_set_font_size(cr, 12);
  draw_y_axis(cr, f);
  draw_x_axis(cr, f);
  cairo_set_source_rgb(cr, 0, 0, 0);
  cairo_rectangle(cr, kLeft, kTop, kPlotRight - kLeft, kPlotBottom - kTop);
  cairo_stroke(cr);
  const bool events = draw_data(cr, f, rows);
  draw_labels(cr, title);
  draw_legend(cr, events);
}

}  // namespace

void write_history_plot(const std::filesystem::path& path, const std::vector<HistoryRow>& rows,
                        const std::string& title) {
  write_atomically(path, [&](const std::filesystem::path& tmp) {
    cairo_surface_t* surface = cairo_image_surface_create(CAIRO_FORMAT_RGB24, kWidth, kHeight);
    cairo_t* cr = cairo_create(surface);
    draw(cr, rows, title);
    cairo_destroy(cr);
    try {
      write_png_file(tmp, surface);
    } catch (...) {
      cairo_surface_destroy(surface);
      throw;
    }
    cairo_surface_destroy(surface);
  });
}

}  // namespace pdmesh
