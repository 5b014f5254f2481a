// A drawing surface for pdmesh pictures (cairo, PNG or SVG): a world window mapped to pixels with
// the aspect ratio preserved, a title band on top, an optional side band (colour bars) and a scale bar.
#pragma once
#include <cairo.h>

#include <filesystem>
#include <functional>
#include <string>

#include "core/vec2.hpp"

namespace pdmesh {

struct Rgb {
  double r = 0, g = 0, b = 0;
};

namespace colours {
inline constexpr Rgb kGeometry{0.0, 0.62, 0.0};   // green, as in the thesis figures
inline constexpr Rgb kBoundaryNode{0.0, 0.0, 0.9};
inline constexpr Rgb kInteriorNode{0.9, 0.0, 0.0};
inline constexpr Rgb kTree{0.6, 0.6, 0.6};
inline constexpr Rgb kBlack{0.0, 0.0, 0.0};
inline constexpr Rgb kWhite{1.0, 1.0, 1.0};
}  // namespace colours

enum class ImageFormat { Png, Svg };

// PNG for ".png", SVG for ".svg"; InputError naming the path otherwise.
ImageFormat image_format_for(const std::filesystem::path& path);

// The window around `extents` with `margin` (a fraction of the larger side) on every side; a
// degenerate box gets a unit-sized window so that a single point still draws.
Box padded_window(const Box& extents, double margin = 0.03);

struct CanvasOptions {
  Box window;               // world region to show
  int long_side = 1600;     // pixels on the longer side of the plot area
  int title_height = 40;    // band above the plot for the title
  int side_width = 0;       // band right of the plot (colour bar); 0 = none
};

class Canvas {
 public:
  // Creates the surface; for SVG, `file` is written as drawing proceeds, for PNG at finish().
  Canvas(const CanvasOptions& options, ImageFormat format, const std::filesystem::path& file);
  ~Canvas();
  Canvas(const Canvas&) = delete;
  Canvas& operator=(const Canvas&) = delete;

  int width() const { return width_; }
  int height() const { return height_; }
  double scale() const { return scale_; }  // pixels per world unit
  Vec2 to_pixel(Vec2 world) const;
  const Box& window() const { return window_; }
  // True when a world box overlaps the visible window (cheap culling of far-away items).
  bool visible(const Box& b) const;
  bool visible(Vec2 p, double radius_px) const;

  // World-space drawing, clipped to the plot area. Widths and radii are in pixels.
  void line(Vec2 a, Vec2 b, Rgb colour, double width_px);
  void dot(Vec2 centre, double radius_px, Rgb colour);
  void rectangle(const Box& b, Rgb colour, double width_px);
  void fill_triangle(Vec2 a, Vec2 b, Vec2 c, Rgb colour);

  // Pixel-space decorations.
  void title(const std::string& text);
  void scale_bar();
  void text(double px, double py, const std::string& s, double size, Rgb colour);
  cairo_t* context() { return cr_; }  // for decorations that need cairo directly (colour bars)
  double plot_right() const { return plot_x0_ + plot_w_; }
  double plot_top() const { return plot_y0_; }
  double plot_height() const { return plot_h_; }

  // Writes the PNG (or completes the SVG) and checks cairo's status; throws Error naming the file.
  void finish();

 private:
  void check(const char* what) const;

  std::filesystem::path file_;
  ImageFormat format_;
  Box window_;
  int width_ = 0, height_ = 0;
  double plot_x0_ = 0, plot_y0_ = 0, plot_w_ = 0, plot_h_ = 0;
  double scale_ = 1, offset_x_ = 0, offset_y_ = 0;
  cairo_surface_t* surface_ = nullptr;
  cairo_t* cr_ = nullptr;
  bool clipped_ = false;
};

// Many segments of one colour and width (or many dots of one colour) drawn as one path: cairo's
// per-call cost dominates pictures of thousands of items, so items are collected into one path and
// stroked (filled) every few thousand items and when the batch ends. Overlapping items of a batch
// are painted once (their union), not blended over each other.
class StrokeBatch {
 public:
  StrokeBatch(Canvas& canvas, Rgb colour, double width_px);
  ~StrokeBatch() { flush(); }
  StrokeBatch(const StrokeBatch&) = delete;
  StrokeBatch& operator=(const StrokeBatch&) = delete;
  void segment(Vec2 a, Vec2 b);  // world coordinates
  void box(const Box& b);        // the outline of a world box
  void flush();

 private:
  Canvas& canvas_;
  Rgb colour_;
  double width_;
  int count_ = 0;
};

class DotBatch {
 public:
  DotBatch(Canvas& canvas, Rgb colour);
  ~DotBatch() { flush(); }
  DotBatch(const DotBatch&) = delete;
  DotBatch& operator=(const DotBatch&) = delete;
  void dot(Vec2 centre, double radius_px);
  void flush();

 private:
  Canvas& canvas_;
  Rgb colour_;
  int count_ = 0;
};

// Draws with `draw` into a new Canvas and writes it atomically to `path` (format by extension).
void render_picture(const std::filesystem::path& path, const CanvasOptions& options,
                    const std::function<void(Canvas&)>& draw);

}  // namespace pdmesh
