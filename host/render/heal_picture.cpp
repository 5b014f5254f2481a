// write_heal_picture() (heal_picture.hpp).
#include "render/heal_picture.hpp"

#include <cmath>
#include <fmt/format.h>

#include "render/canvas.hpp"

namespace pdmesh {

namespace {

constexpr Rgb kInput{0.6, 0.6, 0.6};
constexpr Rgb kRemoved{0.85, 0.0, 0.0};
constexpr Rgb kAdded{0.0, 0.2, 0.9};

void polyline(StrokeBatch& batch, Canvas& canvas, const std::vector<Vec2>& pts) {
  for (std::size_t k = 0; k + 1 < pts.size(); ++k) {
    Box b;
    b.add(pts[k]);
    b.add(pts[k + 1]);
    if (canvas.visible(b)) batch.segment(pts[k], pts[k + 1]);
  }
}

}  // namespace

void write_heal_picture(const std::filesystem::path& path, const std::vector<std::vector<Vec2>>& input,
                        const HealResult& result, const std::string& title, int long_side) {
  Box extents;
  for (const auto& c : input)
    for (Vec2 p : c) extents.add(p);
  CanvasOptions layout;
  layout.window = padded_window(extents);
  layout.long_side = long_side;
  render_picture(path, layout, [&](Canvas& canvas) {
    {
      StrokeBatch grey(canvas, kInput, 1.0);
      for (const auto& c : input) polyline(grey, canvas, c);
    }
    {
      StrokeBatch red(canvas, kRemoved, 2.5);
      for (const HealChange& ch : result.changes) polyline(red, canvas, ch.removed);
    }
    {
      StrokeBatch blue(canvas, kAdded, 2.5);
      for (const HealChange& ch : result.changes) polyline(blue, canvas, ch.added);
    }
    // A ring around each change, red where something was removed without a replacement (an island).
    cairo_t* cr = canvas.context();
    for (const HealChange& ch : result.changes) {
      if (!canvas.visible(ch.at, 10.0)) continue;
      const Vec2 p = canvas.to_pixel(ch.at);
      const Rgb c = ch.added.empty() ? kRemoved : kAdded;
      cairo_set_source_rgb(cr, c.r, c.g, c.b);
      cairo_set_line_width(cr, 1.5);
      cairo_new_sub_path(cr);
      cairo_arc(cr, p.x, p.y, 8.0, 0.0, 2.0 * 3.14159265358979323846);
      cairo_stroke(cr);
    }
    std::string counts;
    for (int k = 0; k < kHealKinds; ++k) {
      const auto kind = static_cast<HealKind>(k);
      if (const int n = result.count(kind))
        counts += fmt::format("{}{} {}", counts.empty() ? "" : ", ", n, to_string(kind));
    }
    canvas.title(fmt::format("{} - healing: {}  (grey input, red removed, blue added)", title, counts));
  });
}

}  // namespace pdmesh
