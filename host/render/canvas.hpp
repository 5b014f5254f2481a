// A drawing surface for pdmesh pictures (cairo, PNG or SVG): a world window mapped to pixels with
// the aspect ratio preserved, a title band on top, an optional side band (colour bars) and a scale bar.
#pragma once
#include <cstddef>
#include <exception>
#include <cairo.h>

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "core/vec2.hpp"

namespace pdmesh {

struct Rgb {
  double r = 0, g = 0, b = 0;
};

namespace colours {
inline constexpr Rgb kGeometry{0.0, 0.62, 0.0};  // green, as in the thesis figures
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
  Box window;             // world region to show
  int long_side = 1600;   // pixels on the longer side of the plot area
  int title_height = 40;  // band above the plot for the title
  int side_width = 0;     // band right of the plot (colour bar); 0 = none
  // Only greys are drawn (a mesh picture without a value fill): a PNG canvas then draws into one
  // byte a pixel (cairo's A8 format, the ink 1 - grey as alpha, every drawing interpolating towards
  // its colour by its coverage as an opaque colour does on RGB), a quarter of the bytes to clear,
  // composite and encode; an SVG draws as usual.
  bool grey = false;
};

// The pixel rows [first, first + count) of a picture that one Canvas draws (count < 0: to the
// bottom). A picture drawn in bands by several threads (render_picture's `bands`) gives each band
// its own surface; the world-to-pixel transform is the whole picture's, shifted by `first` rows.
struct PixelRows {
  int first = 0;
  int count = -1;
};

class Canvas {
 public:
  // Creates the surface; for SVG, `file` is written as drawing proceeds, for PNG at finish().
  Canvas(const CanvasOptions& options, ImageFormat format, const std::filesystem::path& file, PixelRows rows = {});
  ~Canvas();
  Canvas(const Canvas&) = delete;
  Canvas& operator=(const Canvas&) = delete;

  int width() const { return width_; }
  int height() const { return height_; }   // the whole picture's, whatever rows this canvas draws
  double scale() const { return scale_; }  // pixels per world unit
  Vec2 to_pixel(Vec2 world) const;
  const Box& window() const { return window_; }
  // True when a world box overlaps the visible window and this canvas' rows (cheap culling of items
  // no pixel of which this canvas draws).
  bool visible(const Box& b) const;
  bool visible(Vec2 p, double radius_px) const;
  // True when a world box overlaps the visible window, whichever rows this canvas draws (what a
  // picture says about itself, e.g. in its title, must not depend on the band).
  bool in_window(const Box& b) const;

  // World-space drawing, clipped to the plot area. Widths and radii are in pixels.
  void line(Vec2 a, Vec2 b, Rgb colour, double width_px);
  void dot(Vec2 centre, double radius_px, Rgb colour);
  void rectangle(const Box& b, Rgb colour, double width_px);

  // Pixel-space decorations. The title goes in the band above the plot, and a scale bar of 1, 2 or 5
  // times a power of ten world units at the band's right end, beside the title, so that it hides
  // nothing of the drawing; only where the band is too low or the title too long for both does the
  // bar go on a white backing in the plot's bottom-left corner.
  void title(const std::string& text);
  void text(double px, double py, const std::string& s, double size, Rgb colour);
  cairo_t* context() { return cr_; }  // for decorations that need cairo directly (colour bars)
  // Sets cairo's source to an opaque colour (on a grey canvas: its ink, 1 - the mean of its
  // channels, as alpha).
  void set_source(Rgb colour);
  bool grey() const { return grey_; }
  double plot_right() const { return plot_x0_ + plot_w_; }
  double plot_width() const { return plot_w_; }
  double plot_top() const { return plot_y0_; }
  double plot_height() const { return plot_h_; }

  // Writes the PNG (or completes the SVG) and checks cairo's status; throws Error naming the file.
  void finish();
  // Checks cairo's status (throws Error naming the file); for a band, whose rows another writes.
  void check_drawn() const { check("draw"); }
  cairo_surface_t* surface() { return surface_; }
  // A PNG canvas draws into pixels (PixelSplat needs them); an SVG one into vector paths.
  bool raster() const { return format_ == ImageFormat::Png; }
  int first_row() const { return static_cast<int>(rows_lo_); }  // this canvas' rows of the picture
  int end_row() const { return static_cast<int>(rows_hi_); }

 private:
  void scale_bar(double title_right);  // title()'s bar, clear of a title ending at x = title_right
  void check(const char* what) const;
  // Whether pixel rows of the world band [world_lo_y, world_hi_y], widened by slack_px, meet this
  // canvas' rows.
  bool in_rows(double world_lo_y, double world_hi_y, double slack_px) const;

  std::filesystem::path file_;
  ImageFormat format_;
  Box window_;
  int width_ = 0, height_ = 0;
  double plot_x0_ = 0, plot_y0_ = 0, plot_w_ = 0, plot_h_ = 0;
  double scale_ = 1, offset_x_ = 0, offset_y_ = 0;
  double rows_lo_ = 0, rows_hi_ = 0;  // the pixel rows this canvas draws, [lo, hi)
  cairo_surface_t* surface_ = nullptr;
  cairo_t* cr_ = nullptr;
  bool clipped_ = false;
  bool grey_ = false;
};

// Many segments of one colour and width (or many dots of one colour) drawn as one path: cairo's
// per-call cost dominates pictures of thousands of items, so items are collected into one path and
// stroked (filled) every few thousand items and when the batch ends, unless it ends by an exception
// (a stop request: the picture is abandoned, and painting the batch would only delay the stop).
// Overlapping items of a batch are painted once (their union), not blended over each other.
class StrokeBatch {
 public:
  // `cap`: the segments' ends (round: the canvas's default, lines that meet at an angle join
  // without a notch; butt: a thin line's ends, where the round caps cost a sixth of the stroke).
  StrokeBatch(Canvas& canvas, Rgb colour, double width_px, cairo_line_cap_t cap = CAIRO_LINE_CAP_ROUND);
  ~StrokeBatch() {
    if (std::uncaught_exceptions() == 0) flush();
  }
  StrokeBatch(const StrokeBatch&) = delete;
  StrokeBatch& operator=(const StrokeBatch&) = delete;
  void segment(Vec2 a, Vec2 b);  // world coordinates
  void box(const Box& b);        // the outline of a world box
  // A closed polygon through world points as one item: one subpath whose corners join, cheaper for
  // cairo to stroke than its sides as separate segments (each with its two caps).
  void closed_path(const std::vector<Vec2>& points);
  // An item that this canvas does not draw (outside its band) but the whole picture does: counted
  // as drawn, so that every band flushes its batches after the same items as the whole picture and
  // overlapping items blend the same way in every band.
  void skip();
  void flush();

 private:
  Canvas& canvas_;
  Rgb colour_;
  double width_;
  cairo_line_cap_t cap_;
  int count_ = 0;
};

// Many triangles of one colour filled as one path: their union, without the anti-aliasing seams that
// separate fills leave between neighbours (closing them costs a hairline stroke of every outline). A
// mesh with more triangles than one batch holds gets the hairline once per batch, where batches meet,
// unless `close_seams` is false (the caller has covered the seams otherwise). `items` (0: not known), the triangles
// and skips the caller will give: up to kSingleFillItems they are one batch, one fill without the
// hairline. Every band of a picture must be given the same count, so that each cuts its batches at the
// same triangles.
class FillBatch {
 public:
  // Items per batch when they are more than kSingleFillItems or not known.
  static constexpr std::size_t kBatchItems = std::size_t{1} << 16;
  static constexpr std::size_t kSingleFillItems = std::size_t{1} << 18;
  FillBatch(Canvas& canvas, Rgb colour, std::size_t items = 0, bool close_seams = true);
  ~FillBatch() {
    if (std::uncaught_exceptions() == 0) flush();
  }
  FillBatch(const FillBatch&) = delete;
  FillBatch& operator=(const FillBatch&) = delete;
  void triangle(Vec2 a, Vec2 b, Vec2 c);  // world coordinates
  void skip();                            // as StrokeBatch::skip
  void flush(bool cut = false);           // cut: more triangles follow in another batch

 private:
  Canvas& canvas_;
  Rgb colour_;
  std::size_t limit_;  // items per batch
  std::size_t count_ = 0;
  bool cut_ = false;
  bool close_seams_;
};

// Many dots of one colour filled as one path at cairo's fast anti-aliasing. With `pen_radius` > 0,
// the dots of exactly that radius (a node picture's smallest, most of its dots) are drawn instead as
// zero-length segments with round caps, one stroke of width 2 pen_radius: cairo's pen, a circle's
// polygon computed once a stroke, in place of an arc's curves built and flattened for every dot.
// They are painted after the batch's other dots (where the two kinds overlap, they blend).
class DotBatch {
 public:
  DotBatch(Canvas& canvas, Rgb colour, double pen_radius = 0);
  ~DotBatch() {
    if (std::uncaught_exceptions() == 0) flush();
  }
  DotBatch(const DotBatch&) = delete;
  DotBatch& operator=(const DotBatch&) = delete;
  void dot(Vec2 centre, double radius_px);
  void flush();

 private:
  Canvas& canvas_;
  Rgb colour_;
  double pen_radius_ = 0;
  std::vector<Vec2> pen_dots_;  // pixel centres of the dots drawn with the pen
  int count_ = 0;
};

// Items about a pixel in size or smaller, millions of them, as one coverage bitmap that paint() fills
// with one colour in one cairo call: a cairo path costs about a microsecond per item, most of a
// multi-million-node picture's time. A box (a triangle of a dense mesh) covers every pixel its
// pixel-space bounding box meets, so a dense region reads as one solid area. A dot adds its area
// (pi r^2 pixels) to the four pixels around its centre, bilinearly: what shows is the dots' density
// (a pixel is full where they would cover it), without the beats a node lattice near the pixel
// spacing would give, as cairo's anti-aliased dots show it. Pictures use it where
// splat_worthwhile() says so, and keep cairo's paths elsewhere, so smaller pictures keep their
// pixels. A PNG canvas only; a band covers only its own rows, so banded pictures stay pixel for pixel
// one canvas' picture.
class PixelSplat {
 public:
  PixelSplat(Canvas& canvas, Rgb colour);
  ~PixelSplat() {
    if (std::uncaught_exceptions() == 0) paint();
  }
  PixelSplat(const PixelSplat&) = delete;
  PixelSplat& operator=(const PixelSplat&) = delete;
  void box(const Box& world);               // covers the pixels of a world box
  void dot(Vec2 centre, double radius_px);  // adds a dot's area around its centre
  void paint();                             // fills the covered pixels and clears the bitmap

 private:
  void add(int x, int y, float area);  // picture pixel (x, y); nothing outside this canvas

  Canvas& canvas_;
  Rgb colour_;
  int width_ = 0;
  int rows_ = 0;
  std::vector<float> coverage_;  // pixel areas covered, this canvas' rows; 1 = full
  bool any_ = false;
};

// Whether `items` drawn on `canvas` are dense enough for a PixelSplat: a PNG, and more items than a
// quarter of the plot's pixels (a million nodes in a 1600 x 1600 plot, not a 30P30N mesh).
bool splat_worthwhile(const Canvas& canvas, std::size_t items);

// Draws with `draw` into a new Canvas and writes it atomically to `path` (format by extension).
// bands > 1 (PNG only): the picture is cut into that many horizontal bands, each drawn by `draw`
// on a canvas of its own, by the caller and up to (cores - 1) threads, and the bands are written as
// one PNG, pixel for pixel the picture one canvas draws when `draw` culls with Canvas::visible and
// skips what it culls in its batches (StrokeBatch::skip). `draw` must then be safe to call from
// several threads at once (reading shared data only). A mesh picture drawn after the cleanup is on
// the run's critical path, and cairo's rasteriser is single-threaded.
void render_picture(const std::filesystem::path& path, const CanvasOptions& options,
                    const std::function<void(Canvas&)>& draw, int bands = 1);

}  // namespace pdmesh
