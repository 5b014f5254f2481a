// Canvas: cairo surfaces (image or SVG), the world-to-pixel transform, clipping, decorations.
#include "render/canvas.hpp"

#include <cairo-svg.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <exception>
#include <memory>
#include <thread>
#include <vector>
#include <fmt/format.h>

#include "core/interrupt.hpp"
#include "core/atomic_file.hpp"
#include "core/errors.hpp"
#include "render/png_file.hpp"

namespace pdmesh {

namespace fs = std::filesystem;

ImageFormat image_format_for(const fs::path& path) {
  const std::string ext = path.extension().string();
  if (ext == ".png") return ImageFormat::Png;
  if (ext == ".svg") return ImageFormat::Svg;
  throw InputError(fmt::format("cannot draw '{}': pictures are .png or .svg", path.string()));
}

Box padded_window(const Box& extents, double margin) {
  Box w = extents;
  if (!(w.lo.x <= w.hi.x && w.lo.y <= w.hi.y)) w = Box{{0, 0}, {0, 0}};
  double span = std::max(w.width(), w.height());
  if (!(span > 0)) span = 1.0;
  const double pad = margin * span;
  // A very thin geometry still gets a visible band across its short side.
  const double min_half = 0.05 * span;
  const Vec2 c = w.centre();
  const double hx = std::max(0.5 * w.width(), min_half) + pad;
  const double hy = std::max(0.5 * w.height(), min_half) + pad;
  return Box{{c.x - hx, c.y - hy}, {c.x + hx, c.y + hy}};
}

Canvas::Canvas(const CanvasOptions& options, ImageFormat format, const fs::path& file, PixelRows rows)
    : file_(file), format_(format), window_(options.window) {
  const double ww = window_.width(), wh = window_.height();
  if (!(ww > 0 && wh > 0) || !std::isfinite(ww) || !std::isfinite(wh)) {
    throw InputError(fmt::format("cannot draw '{}': empty or non-finite window [{}, {}] x [{}, {}]", file.string(),
                                 window_.lo.x, window_.hi.x, window_.lo.y, window_.hi.y));
  }
  const int long_side = std::clamp(options.long_side, 64, 20000);
  // The short side follows the window's aspect ratio, but never so thin that the title is lost.
  const double aspect = ww / wh;
  plot_w_ = aspect >= 1 ? long_side : std::max(160.0, std::round(long_side * aspect));
  plot_h_ = aspect >= 1 ? std::max(160.0, std::round(long_side / aspect)) : long_side;
  plot_x0_ = 0;
  plot_y0_ = options.title_height;
  width_ = static_cast<int>(plot_w_) + options.side_width;
  height_ = static_cast<int>(plot_h_) + options.title_height;
  scale_ = std::min(plot_w_ / ww, plot_h_ / wh);
  offset_x_ = plot_x0_ + 0.5 * (plot_w_ - scale_ * ww);
  offset_y_ = plot_y0_ + 0.5 * (plot_h_ - scale_ * wh);

  const int first = std::clamp(rows.first, 0, height_);
  const int count = rows.count < 0 ? height_ - first : std::min(rows.count, height_ - first);
  if (format != ImageFormat::Png && (first != 0 || count != height_))
    throw Error(fmt::format("cannot draw '{}': only a PNG is drawn in bands", file.string()));
  rows_lo_ = first;
  rows_hi_ = first + count;
  grey_ = options.grey && format == ImageFormat::Png;
  surface_ = format == ImageFormat::Png
                 ? cairo_image_surface_create(grey_ ? CAIRO_FORMAT_A8 : CAIRO_FORMAT_RGB24, width_, std::max(count, 1))
                 : cairo_svg_surface_create(file.c_str(), width_, height_);
  cr_ = cairo_create(surface_);
  // A band draws the whole picture's pixel coordinates shifted up by its first row (an integer, so
  // every pixel's coverage is the one the whole picture gives it).
  if (first != 0) cairo_translate(cr_, 0, -first);
  try {
    check("create the surface");
  } catch (...) {
    // The destructor does not run for a half-built object.
    cairo_destroy(cr_);
    cairo_surface_destroy(surface_);
    throw;
  }
  if (grey_) {
    // A new image surface is all zero: no ink, white. Each drawing interpolates from what is there
    // towards its ink by its coverage (an opaque colour over RGB does the same).
    cairo_set_operator(cr_, CAIRO_OPERATOR_SOURCE);
  } else {
    cairo_set_source_rgb(cr_, 1, 1, 1);
    cairo_paint(cr_);
  }
  cairo_set_line_cap(cr_, CAIRO_LINE_CAP_ROUND);
  cairo_set_line_join(cr_, CAIRO_LINE_JOIN_ROUND);
  cairo_select_font_face(cr_, "sans-serif", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
  cairo_save(cr_);
  cairo_rectangle(cr_, plot_x0_, plot_y0_, plot_w_, plot_h_);
  cairo_clip(cr_);
  clipped_ = true;
}

Canvas::~Canvas() {
  if (cr_ != nullptr) cairo_destroy(cr_);
  if (surface_ != nullptr) cairo_surface_destroy(surface_);
}

void Canvas::check(const char* what) const {
  const cairo_status_t s = cr_ != nullptr ? cairo_status(cr_) : cairo_surface_status(surface_);
  const cairo_status_t ss = cairo_surface_status(surface_);
  const cairo_status_t bad = s != CAIRO_STATUS_SUCCESS ? s : ss;
  if (bad != CAIRO_STATUS_SUCCESS) {
    throw Error(
        fmt::format("cannot draw '{}': cairo could not {}: {}", file_.string(), what, cairo_status_to_string(bad)));
  }
}

Vec2 Canvas::to_pixel(Vec2 w) const {
  return {offset_x_ + (w.x - window_.lo.x) * scale_, offset_y_ + (window_.hi.y - w.y) * scale_};
}

bool Canvas::in_window(const Box& b) const {
  const double slack = 8.0 / scale_;  // line widths and dot radii reach a few pixels beyond
  return b.hi.x >= window_.lo.x - slack && b.lo.x <= window_.hi.x + slack && b.hi.y >= window_.lo.y - slack &&
         b.lo.y <= window_.hi.y + slack;
}

bool Canvas::visible(const Box& b) const { return in_window(b) && in_rows(b.lo.y, b.hi.y, 8.0); }

bool Canvas::visible(Vec2 p, double radius_px) const {
  const double r = radius_px / scale_;
  return p.x >= window_.lo.x - r && p.x <= window_.hi.x + r && p.y >= window_.lo.y - r && p.y <= window_.hi.y + r &&
         in_rows(p.y, p.y, radius_px + 1.0);
}

bool Canvas::in_rows(double world_lo_y, double world_hi_y, double slack_px) const {
  // Pixel rows grow downwards: the box's top edge (world_hi_y) is its first row.
  const double top = offset_y_ + (window_.hi.y - world_hi_y) * scale_;
  const double bottom = offset_y_ + (window_.hi.y - world_lo_y) * scale_;
  return !(bottom < rows_lo_ - slack_px) && !(top > rows_hi_ + slack_px);
}

void Canvas::set_source(Rgb c) {
  if (grey_)
    cairo_set_source_rgba(cr_, 0, 0, 0, 1.0 - (c.r + c.g + c.b) / 3.0);
  else
    cairo_set_source_rgb(cr_, c.r, c.g, c.b);
}

void Canvas::line(Vec2 a, Vec2 b, Rgb c, double width_px) {
  const Vec2 pa = to_pixel(a), pb = to_pixel(b);
  set_source(c);
  cairo_set_line_width(cr_, width_px);
  cairo_move_to(cr_, pa.x, pa.y);
  cairo_line_to(cr_, pb.x, pb.y);
  cairo_stroke(cr_);
}

void Canvas::dot(Vec2 centre, double radius_px, Rgb c) {
  const Vec2 p = to_pixel(centre);
  set_source(c);
  cairo_new_sub_path(cr_);
  cairo_arc(cr_, p.x, p.y, radius_px, 0, 2 * M_PI);
  cairo_fill(cr_);
}

void Canvas::rectangle(const Box& b, Rgb c, double width_px) {
  const Vec2 p0 = to_pixel(b.lo), p1 = to_pixel(b.hi);
  set_source(c);
  cairo_set_line_width(cr_, width_px);
  cairo_rectangle(cr_, p0.x, p1.y, p1.x - p0.x, p0.y - p1.y);
  cairo_stroke(cr_);
}

void Canvas::text(double px, double py, const std::string& s, double size, Rgb c) {
  set_source(c);
  cairo_set_font_size(cr_, size);
  cairo_move_to(cr_, px, py);
  cairo_show_text(cr_, s.c_str());
}

void Canvas::title(const std::string& s) {
  if (clipped_) cairo_restore(cr_);
  const double size = std::min(18.0, plot_y0_ * 0.5);
  text(12, plot_y0_ * 0.7, s, size, colours::kBlack);
  cairo_text_extents_t extent;
  cairo_text_extents(cr_, s.c_str(), &extent);  // at the title's font size, which text() set
  scale_bar(12 + extent.x_advance);
  cairo_save(cr_);
  cairo_rectangle(cr_, plot_x0_, plot_y0_, plot_w_, plot_h_);
  cairo_clip(cr_);
}

void Canvas::scale_bar(double title_right) {
  // The longest 1, 2 or 5 times a power of ten that fits in a fifth of the plot width.
  const double target = 0.2 * plot_w_ / scale_;
  const double power = std::pow(10.0, std::floor(std::log10(target)));
  double length = power;
  for (double m : {2.0, 5.0}) {
    if (m * power <= target) length = m * power;
  }
  const double px = length * scale_;
  // In the band: the bar's baseline 8 px above the plot, its label above it, its right end 20 px in
  // from the plot's right edge; it needs the band at least 32 px high and 24 px clear of the title.
  const double band_x0 = plot_x0_ + plot_w_ - 20 - px;
  const bool in_band = plot_y0_ >= 32 && band_x0 - 24 >= title_right;
  const double x0 = in_band ? band_x0 : plot_x0_ + 20;
  const double y0 = in_band ? plot_y0_ - 8 : plot_y0_ + plot_h_ - 20;
  if (!in_band) {
    if (grey_) {  // a fifth of the ink left, as white at alpha 0.8 over RGB leaves
      cairo_save(cr_);
      cairo_set_operator(cr_, CAIRO_OPERATOR_DEST_OUT);
      cairo_set_source_rgba(cr_, 0, 0, 0, 0.8);
      cairo_rectangle(cr_, x0 - 8, y0 - 30, px + 16, 40);
      cairo_fill(cr_);
      cairo_restore(cr_);
    } else {
      cairo_set_source_rgba(cr_, 1, 1, 1, 0.8);
      cairo_rectangle(cr_, x0 - 8, y0 - 30, px + 16, 40);
      cairo_fill(cr_);
    }
  }
  set_source(colours::kBlack);
  cairo_set_line_width(cr_, 2);
  cairo_move_to(cr_, x0, y0 - 6);
  cairo_line_to(cr_, x0, y0);
  cairo_line_to(cr_, x0 + px, y0);
  cairo_line_to(cr_, x0 + px, y0 - 6);
  cairo_stroke(cr_);
  text(x0, y0 - 10, fmt::format("{:g}", length), 14, colours::kBlack);
}

void Canvas::finish() {
  check("draw");
  if (format_ == ImageFormat::Png) {
    write_png_file(file_, surface_);
  } else {
    cairo_surface_finish(surface_);
    check("write the SVG");
  }
}

namespace {
// Items per stroke or dot batch (FillBatch has its own, kBatchItems): large enough that cairo's
// per-call cost vanishes, small enough that the path it tessellates at once stays in cache.
constexpr int kPathBatchItems = 4096;
}  // namespace

StrokeBatch::StrokeBatch(Canvas& canvas, Rgb colour, double width_px, cairo_line_cap_t cap)
    : canvas_(canvas), colour_(colour), width_(width_px), cap_(cap) {
  cairo_new_path(canvas_.context());
}

void StrokeBatch::segment(Vec2 a, Vec2 b) {
  const Vec2 pa = canvas_.to_pixel(a), pb = canvas_.to_pixel(b);
  cairo_t* cr = canvas_.context();
  cairo_move_to(cr, pa.x, pa.y);
  cairo_line_to(cr, pb.x, pb.y);
  if (++count_ >= kPathBatchItems) flush();
}

void StrokeBatch::box(const Box& b) {
  const Vec2 p0 = canvas_.to_pixel(b.lo), p1 = canvas_.to_pixel(b.hi);
  cairo_rectangle(canvas_.context(), p0.x, p1.y, p1.x - p0.x, p0.y - p1.y);
  if (++count_ >= kPathBatchItems) flush();
}

void StrokeBatch::closed_path(const std::vector<Vec2>& points) {
  if (points.empty()) return;
  cairo_t* cr = canvas_.context();
  const Vec2 p0 = canvas_.to_pixel(points.front());
  cairo_move_to(cr, p0.x, p0.y);
  for (std::size_t k = 1; k < points.size(); ++k) {
    const Vec2 p = canvas_.to_pixel(points[k]);
    cairo_line_to(cr, p.x, p.y);
  }
  cairo_close_path(cr);
  if (++count_ >= kPathBatchItems) flush();
}

void StrokeBatch::skip() {
  if (++count_ >= kPathBatchItems) flush();
}

void StrokeBatch::flush() {
  if (count_ == 0) return;
  cairo_t* cr = canvas_.context();
  if (!cairo_has_current_point(cr)) {  // only skipped items since the last flush
    count_ = 0;
    return;
  }
  canvas_.set_source(colour_);
  cairo_set_line_width(cr, width_);
  cairo_set_line_cap(cr, cap_);
  cairo_stroke(cr);                              // also clears the path
  cairo_set_line_cap(cr, CAIRO_LINE_CAP_ROUND);  // the canvas's own cap
  count_ = 0;
}

FillBatch::FillBatch(Canvas& canvas, Rgb colour, std::size_t items, bool close_seams)
    : canvas_(canvas),
      colour_(colour),
      // Triangles per fill: one fill is their union, seamless, so as many as memory allows (a cairo
      // path holds ~100 bytes a triangle). A known count up to kSingleFillItems is one fill: the
      // hairline stroke that closes the seams between batches takes several times the fill's time
      // and memory (cairo strokes every triangle's outline). One past the count: the last item does
      // not cut a batch that holds them all.
      limit_(items > kBatchItems && items <= kSingleFillItems ? items + 1 : kBatchItems),
      close_seams_(close_seams) {
  cairo_new_path(canvas_.context());
}

void FillBatch::triangle(Vec2 a, Vec2 b, Vec2 c) {
  const Vec2 pa = canvas_.to_pixel(a), pb = canvas_.to_pixel(b), pc = canvas_.to_pixel(c);
  cairo_t* cr = canvas_.context();
  cairo_move_to(cr, pa.x, pa.y);
  cairo_line_to(cr, pb.x, pb.y);
  cairo_line_to(cr, pc.x, pc.y);
  cairo_close_path(cr);
  if (++count_ >= limit_) flush(true);
}

void FillBatch::skip() {
  if (++count_ >= limit_) flush(true);
}

void FillBatch::flush(bool cut) {
  if (count_ == 0) return;
  cairo_t* cr = canvas_.context();
  count_ = 0;
  cut_ = cut_ || cut;
  if (!cairo_has_current_point(cr)) return;  // only skipped items since the last flush
  canvas_.set_source(colour_);
  if (!cut_ || !close_seams_) {
    cairo_fill(cr);  // the union of every triangle: no seams inside it
    return;
  }
  // Several anti-aliased batches: a hairline stroke in the fill colour closes the anti-aliasing seams where two
  // batches meet (bevel joins: round ones cost most of the stroke at these sizes).
  cairo_fill_preserve(cr);
  cairo_save(cr);
  cairo_set_line_width(cr, 0.5);
  cairo_set_line_join(cr, CAIRO_LINE_JOIN_BEVEL);
  cairo_stroke(cr);  // also clears the path
  cairo_restore(cr);
}

DotBatch::DotBatch(Canvas& canvas, Rgb colour, double pen_radius)
    : canvas_(canvas), colour_(colour), pen_radius_(pen_radius) {
  cairo_new_path(canvas_.context());
}

void DotBatch::dot(Vec2 centre, double radius_px) {
  const Vec2 p = canvas_.to_pixel(centre);
  if (pen_radius_ > 0 && radius_px == pen_radius_) {
    pen_dots_.push_back(p);
  } else {
    cairo_t* cr = canvas_.context();
    cairo_new_sub_path(cr);
    cairo_arc(cr, p.x, p.y, radius_px, 0, 2 * M_PI);
  }
  if (++count_ >= kPathBatchItems) flush();
}

void DotBatch::flush() {
  if (count_ == 0) return;
  cairo_t* cr = canvas_.context();
  canvas_.set_source(colour_);
  // Dots at 4 x 4 samples a pixel (cairo's "fast" anti-aliasing): a dot of a few pixels looks the
  // same as at the default's finer sampling, for much less of the node picture's time.
  cairo_set_antialias(cr, CAIRO_ANTIALIAS_FAST);
  cairo_fill(cr);  // an empty path (only pen dots) paints nothing
  if (!pen_dots_.empty()) {
    for (const Vec2& p : pen_dots_) {
      cairo_move_to(cr, p.x, p.y);
      cairo_line_to(cr, p.x, p.y);  // zero length: a round cap at each end, a disc
    }
    cairo_set_line_width(cr, 2 * pen_radius_);
    cairo_set_line_cap(cr, CAIRO_LINE_CAP_ROUND);  // the canvas's own cap, set again to be sure
    cairo_stroke(cr);
    pen_dots_.clear();
  }
  cairo_set_antialias(cr, CAIRO_ANTIALIAS_DEFAULT);
  count_ = 0;
}

PixelSplat::PixelSplat(Canvas& canvas, Rgb colour) : canvas_(canvas), colour_(colour) {
  width_ = canvas.width();
  rows_ = std::max(canvas.end_row() - canvas.first_row(), 1);
  coverage_.assign(static_cast<std::size_t>(width_) * static_cast<std::size_t>(rows_), 0.0f);
}

void PixelSplat::add(int x, int y, float area) {
  const int row = y - canvas_.first_row();
  if (x < 0 || x >= width_ || row < 0 || row >= rows_) return;
  coverage_[static_cast<std::size_t>(row) * static_cast<std::size_t>(width_) + static_cast<std::size_t>(x)] += area;
  any_ = true;
}

void PixelSplat::box(const Box& world) {
  // Pixel i covers [i, i + 1): the box meets pixels floor(lo) to floor(hi). Clamped in double first,
  // so far-away items cannot overflow the integer conversion.
  const Vec2 a = canvas_.to_pixel(world.lo), b = canvas_.to_pixel(world.hi);  // world y up, rows down
  const double first = canvas_.first_row(), end = first + rows_;
  const double x0 = std::floor(std::max(a.x, 0.0)), x1 = std::floor(std::min(b.x, width_ - 1.0));
  const double y0 = std::floor(std::max(b.y, first)), y1 = std::floor(std::min(a.y, end - 1.0));
  if (!(x0 <= x1 && y0 <= y1)) return;
  for (int y = static_cast<int>(y0); y <= static_cast<int>(y1); ++y) {
    for (int x = static_cast<int>(x0); x <= static_cast<int>(x1); ++x) add(x, y, 1.0f);
  }
}

void PixelSplat::dot(Vec2 centre, double radius_px) {
  const Vec2 p = canvas_.to_pixel(centre);
  const double fx = p.x - 0.5, fy = p.y - 0.5;  // pixel (i, j)'s centre is (i + 0.5, j + 0.5)
  if (!(std::abs(fx) < 1e9 && std::abs(fy) < 1e9)) return;
  const double ix = std::floor(fx), iy = std::floor(fy);
  const double tx = fx - ix, ty = fy - iy;
  const double area = M_PI * radius_px * radius_px;
  const int x = static_cast<int>(ix), y = static_cast<int>(iy);
  add(x, y, static_cast<float>(area * (1 - tx) * (1 - ty)));
  add(x + 1, y, static_cast<float>(area * tx * (1 - ty)));
  add(x, y + 1, static_cast<float>(area * (1 - tx) * ty));
  add(x + 1, y + 1, static_cast<float>(area * tx * ty));
}

void PixelSplat::paint() {
  if (!any_) return;
  any_ = false;
  const int stride = cairo_format_stride_for_width(CAIRO_FORMAT_A8, width_);
  std::vector<unsigned char> alpha(static_cast<std::size_t>(stride) * static_cast<std::size_t>(rows_), 0);
  for (int row = 0; row < rows_; ++row) {
    const float* c = coverage_.data() + static_cast<std::size_t>(row) * static_cast<std::size_t>(width_);
    unsigned char* out = alpha.data() + static_cast<std::size_t>(row) * static_cast<std::size_t>(stride);
    for (int x = 0; x < width_; ++x) out[x] = static_cast<unsigned char>(std::lround(255.0f * std::min(c[x], 1.0f)));
  }
  cairo_surface_t* mask = cairo_image_surface_create_for_data(alpha.data(), CAIRO_FORMAT_A8, width_, rows_, stride);
  cairo_t* cr = canvas_.context();
  canvas_.set_source(colour_);
  // The context is translated up by the canvas' first row: the mask's row 0 is that row.
  cairo_mask_surface(cr, mask, 0, canvas_.first_row());
  cairo_surface_destroy(mask);
  std::fill(coverage_.begin(), coverage_.end(), 0.0f);
  canvas_.check_drawn();
}

bool splat_worthwhile(const Canvas& canvas, std::size_t items) {
  return canvas.raster() && static_cast<double>(items) > 0.25 * canvas.plot_width() * canvas.plot_height();
}

void render_picture(const fs::path& path, const CanvasOptions& options, const std::function<void(Canvas&)>& draw,
                    int bands) {
  const ImageFormat format = image_format_for(path);
  if (format != ImageFormat::Png || bands <= 1) {
    write_atomically(path, [&](const fs::path& tmp) {
      Canvas canvas(options, format, tmp);
      draw(canvas);
      canvas.finish();
    });
    return;
  }
  write_atomically(path, [&](const fs::path& tmp) {
    // The picture's height, from a canvas that draws no row.
    const int height = Canvas(options, format, tmp, PixelRows{0, 1}).height();
    bands = std::clamp(bands, 1, std::max(1, height / 64));
    std::vector<std::unique_ptr<Canvas>> canvases;
    for (int k = 0; k < bands; ++k) {
      const int first = static_cast<int>(static_cast<long long>(height) * k / bands);
      const int next = static_cast<int>(static_cast<long long>(height) * (k + 1) / bands);
      canvases.push_back(std::make_unique<Canvas>(options, format, tmp, PixelRows{first, next - first}));
    }
    // The bands go to the caller and up to (cores - 1) threads, each taking the next band not yet
    // drawn (the work is uneven: a mesh's dense parts cost most); the first failure is rethrown
    // after every thread has ended.
    std::vector<std::exception_ptr> failed(static_cast<std::size_t>(bands));
    std::vector<DeflatedBand> deflated(static_cast<std::size_t>(bands));
    std::atomic<int> next_band{0};
    const auto draw_bands = [&] {
      for (int k = next_band++; k < bands; k = next_band++) {
        try {
          Canvas& canvas = *canvases[static_cast<std::size_t>(k)];
          check_interrupt();  // a stop request abandons the picture (its temporary is removed)
          draw(canvas);
          canvas.check_drawn();
          check_interrupt();
          // Encoded where it was drawn, while other bands are still being drawn; grey if this band
          // is (most likely the whole picture is too).
          deflated[static_cast<std::size_t>(k)] =
              deflate_band(canvas.surface(), k == bands - 1, 1, grey_surface(canvas.surface()));
        } catch (...) {
          failed[static_cast<std::size_t>(k)] = std::current_exception();
        }
      }
    };
    const int helpers = std::min(bands, static_cast<int>(std::max(1u, std::thread::hardware_concurrency()))) - 1;
    std::vector<std::thread> threads;
    for (int t = 0; t < helpers; ++t) threads.emplace_back(draw_bands);
    draw_bands();
    for (std::thread& t : threads) t.join();
    for (const std::exception_ptr& e : failed)
      if (e) std::rethrow_exception(e);
    check_interrupt();
    // A picture with colour in some bands only: its grey bands again as RGB (one PNG, one colour type).
    const bool all_grey = std::all_of(deflated.begin(), deflated.end(), [](const DeflatedBand& b) { return b.grey; });
    for (int k = 0; k < bands && !all_grey; ++k) {
      if (deflated[static_cast<std::size_t>(k)].grey)
        deflated[static_cast<std::size_t>(k)] =
            deflate_band(canvases[static_cast<std::size_t>(k)]->surface(), k == bands - 1);
    }
    write_bytes(tmp, png_from_bands(deflated));
  });
}

}  // namespace pdmesh
