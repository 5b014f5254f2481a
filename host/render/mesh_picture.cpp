// Mesh pictures: value or region fill, edges, boundary edges and region interfaces, then the colour
// bar or the region legend in a band on the right.
#include "render/mesh_picture.hpp"

#include <optional>

#include <algorithm>
#include <array>
#include <cmath>
#include <mutex>
#include <tuple>
#include <fmt/format.h>

#include "core/errors.hpp"
#include "core/interrupt.hpp"
#include "core/parallel.hpp"
#include "mesh/quality.hpp"
#include "render/fill_groups.hpp"
#include "render/region_fill.hpp"

namespace pdmesh {

namespace {

constexpr int kMeshBarBand = 150;
constexpr Rgb kNoValue{0.75, 0.75, 0.75};  // non-finite values
// Interior edges shorter than kMinEdgePixels on screen are not drawn; triangles with one are shaded
// kDenseShade (without a value fill).
constexpr Rgb kDenseShade{0.55, 0.55, 0.55};

// Samples of matplotlib's viridis at t = 0, 1/8, ..., 1, interpolated linearly in between.
constexpr std::array<Rgb, 9> kViridis = {{{0.267, 0.005, 0.329},
                                          {0.283, 0.141, 0.458},
                                          {0.254, 0.265, 0.530},
                                          {0.207, 0.372, 0.553},
                                          {0.164, 0.471, 0.558},
                                          {0.128, 0.567, 0.551},
                                          {0.135, 0.659, 0.518},
                                          {0.478, 0.821, 0.318},
                                          {0.993, 0.906, 0.144}}};

void draw_colour_bar(Canvas& canvas, double lo, double hi, const std::string& label) {
  const ColourBarBox b = draw_colour_ramp_bar(canvas);
  canvas.text(b.x + b.width + 6, b.top + 5, fmt::format("{:.4g}", hi), 14, colours::kBlack);
  canvas.text(b.x + b.width + 6, b.top + b.height + 5, fmt::format("{:.4g}", lo), 14, colours::kBlack);
  canvas.text(b.x - 20, b.top - 14, label, 14, colours::kBlack);
}

// Throws Error unless there is one value per triangle (when there are values) and every triangle and
// boundary edge names points of the mesh.
void check_picture_inputs(const std::filesystem::path& path, const Mesh& mesh, const std::vector<double>* values) {
  if (values != nullptr && values->size() != mesh.triangles.size()) {
    throw Error(fmt::format("mesh picture '{}': {} values for {} triangles", path.string(), values->size(),
                            mesh.triangles.size()));
  }
  const auto n = static_cast<int>(mesh.points.size());
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    for (int v : mesh.triangles[t]) {
      if (v < 0 || v >= n) throw Error(fmt::format("mesh picture: triangle {} has point index {} of {}", t, v, n));
    }
  }
  for (const BoundaryEdge& e : mesh.boundary_edges) {
    if (e.a < 0 || e.a >= n || e.b < 0 || e.b >= n) {
      throw Error(fmt::format("mesh picture: boundary edge {}-{} is outside the {} points", e.a, e.b, n));
    }
  }
}

// The values at the two ends of the colour ramp: the options' range, else the values' finite minimum
// and maximum (infinite when there are none).
std::pair<double, double> ramp_range(const std::vector<double>* values, const MeshPictureOptions& options) {
  double lo = INFINITY, hi = -INFINITY;
  if (values != nullptr && options.value_range) {
    std::tie(lo, hi) = *options.value_range;
  } else if (values != nullptr) {
    for (double v : *values) {
      if (std::isfinite(v)) {
        lo = std::min(lo, v);
        hi = std::max(hi, v);
      }
    }
  }
  return {lo, hi};
}

// Interior edges shorter than kMinEdgePixels on screen are left out: at millions of triangles they
// would only paint the whole mesh black. `min_edge_world` is that length in world units.
bool shown(Vec2 a, Vec2 b, double min_edge_world) { return dist(a, b) >= min_edge_world; }

// Without a value fill, a triangle with an edge too short to draw is shaded grey instead, so dense
// parts read as meshed, not as empty.
// In a mesh of more triangles than a quarter of the plot's pixels, a triangle whose three edges are
// all too short spans at most a few pixels and is set in a PixelSplat (its bounding box's pixels)
// instead of a path: the union is what shows, at a fraction of the cost.
void draw_dense_shade(Canvas& canvas, const Mesh& mesh, double min_edge_world) {
  std::optional<PixelSplat> splat;
  if (splat_worthwhile(canvas, mesh.triangles.size())) splat.emplace(canvas, kDenseShade);
  // The triangles in the window with an edge too short to draw, but for those the splat takes: the fill
  // batch's items, the same count in every band (FillBatch). `shaded` also gives the triangle's box
  // and whether all three of its edges are too short.
  const auto shaded = [&](const std::array<int, 3>& tri, Box& box, bool& all_short) {
    const Vec2 a = mesh.points[tri[0]], b = mesh.points[tri[1]], c = mesh.points[tri[2]];
    const bool ab = shown(a, b, min_edge_world), bc = shown(b, c, min_edge_world), ca = shown(c, a, min_edge_world);
    all_short = !ab && !bc && !ca;
    if (ab && bc && ca) return false;
    box = Box{};
    for (int v : tri) box.add(mesh.points[v]);
    return canvas.in_window(box);
  };
  std::size_t items = 0;  // not counted where they cannot fill more than one batch
  if (mesh.triangles.size() > FillBatch::kBatchItems) {
    InterruptPoll poll(65536);
    for (const auto& tri : mesh.triangles) {
      poll.tick();
      Box box;
      bool all_short = false;
      items += shaded(tri, box, all_short) && !(splat && all_short);
    }
  }
  FillBatch dense(canvas, kDenseShade, items);
  InterruptPoll poll(65536);
  for (const auto& tri : mesh.triangles) {
    poll.tick();
    Box box;
    bool all_short = false;
    if (!shaded(tri, box, all_short)) continue;
    if (splat && all_short) {
      if (canvas.visible(box)) splat->box(box);
    } else if (canvas.visible(box)) {
      dense.triangle(mesh.points[tri[0]], mesh.points[tri[1]], mesh.points[tri[2]]);
    } else {
      dense.skip();  // in another band (see draw_edges)
    }
  }
}

// The colour ramp's levels a value fill uses: more than an 8-bit channel tells apart along viridis.
constexpr std::uint32_t kRampLevels = 256;

// Each triangle's value as one of kRampLevels levels of the ramp between lo and hi (equal extremes:
// every triangle has the same value, shown mid-ramp), or a last group, kNoValue, for non-finite ones.
FillGroups value_fill_groups(const std::vector<double>& values, double lo, double hi) {
  std::vector<std::uint32_t> group_of(values.size());
  for (std::size_t t = 0; t < values.size(); ++t) {
    const double v = values[t];
    const double u = hi > lo ? (v - lo) / (hi - lo) : 0.5;
    group_of[t] = std::isfinite(v) && std::isfinite(u)
                      ? static_cast<std::uint32_t>(std::lround(std::clamp(u, 0.0, 1.0) * (kRampLevels - 1)))
                      : kRampLevels;
  }
  std::vector<Rgb> colours;
  for (std::uint32_t k = 0; k < kRampLevels; ++k) colours.push_back(colour_ramp(k / double(kRampLevels - 1)));
  colours.push_back(kNoValue);
  return group_fills(group_of, std::move(colours));
}

}  // namespace

// Edges stroked together in the order of the mesh start and end in nearly every pixel row, so cairo
// sampled the long edges of a mesh's coarse parts, most of its rows, 15 times a row; stroked apart
// from the edges in the same rows, they are sampled so in their end rows only. The long edges are
// taken in order of their top row, each into a stroke whose edges all end above it, or into a new
// stroke when none does (as many strokes as the most long edges in one row). No two edges of such a
// stroke share a pixel, so each is painted on its own (where edges meet at a vertex, their coverages
// blend as two strokes' do). Short edges gain nothing apart (their rows are all end rows) and stay
// together: in a dense part, lines a fraction of a pixel apart add their coverages as one stroke's
// union does, where blending them would paint the part a shade lighter.
EdgeStrokes plan_edge_strokes(const Canvas& canvas, const Mesh& mesh, const std::vector<std::pair<int, int>>& edges) {
  const double min_edge_world = kMinEdgePixels / canvas.scale();
  // Rows as indices 0 .. rows - 1: the picture's rows, and one above and one below it for the parts
  // of edges outside the picture (clipped away: how they group does not matter).
  const int rows = canvas.height() + 2;
  const auto row_of = [&](double y) {
    return static_cast<int>(std::clamp(std::floor(y), -1.0, static_cast<double>(rows - 2))) + 1;
  };
  struct Item {
    std::size_t edge;
    int top, bottom;
  };
  std::vector<Item> items;
  items.reserve(edges.size());
  std::vector<std::size_t> dense;
  EdgeStrokes plan;
  InterruptPoll poll(65536);
  for (std::size_t k = 0; k < edges.size(); ++k) {
    poll.tick();
    const Vec2 a = mesh.points[static_cast<std::size_t>(edges[k].first)];
    const Vec2 b = mesh.points[static_cast<std::size_t>(edges[k].second)];
    Box box;
    box.add(a);
    box.add(b);
    if (!canvas.in_window(box)) continue;
    if (!shown(a, b, min_edge_world)) {
      ++plan.too_short;  // counted over the whole window: every band draws the same title
      continue;
    }
    const Vec2 pa = canvas.to_pixel(a), pb = canvas.to_pixel(b);
    if (dist(pa, pb) < kApartEdgePixels) {
      dense.push_back(k);
      continue;
    }
    items.push_back({k, row_of(std::min(pa.y, pb.y) - 0.5), row_of(std::max(pa.y, pb.y) + 0.5)});
  }
  // The short edges first, in the mesh's order, as one group (StrokeBatch strokes it in batches).
  for (const std::size_t k : dense) plan.edges.push_back(edges[k]);
  if (!dense.empty()) plan.ends.push_back(plan.edges.size());
  // The items by top row (in edge order within a row).
  std::vector<std::size_t> first(static_cast<std::size_t>(rows) + 1, 0);
  for (const Item& item : items) ++first[static_cast<std::size_t>(item.top) + 1];
  for (std::size_t r = 1; r < first.size(); ++r) first[r] += first[r - 1];
  std::vector<std::size_t> by_top(items.size());
  {
    std::vector<std::size_t> next(first.begin(), first.end() - 1);
    for (std::size_t k = 0; k < items.size(); ++k) by_top[next[static_cast<std::size_t>(items[k].top)]++] = k;
  }
  // Row by row: the strokes whose last edge ends in the row above become idle; each item goes to an
  // idle stroke, or a new one. ending[r]: the strokes whose last edge ends in row r (linked through
  // `later`).
  constexpr int kNone = -1;
  std::vector<int> ending(static_cast<std::size_t>(rows), kNone), later, idle, stroke_of(items.size());
  int strokes = 0;
  for (int r = 0; r < rows; ++r) {
    if (r > 0) {
      for (int s = ending[static_cast<std::size_t>(r - 1)]; s != kNone; s = later[static_cast<std::size_t>(s)])
        idle.push_back(s);
    }
    for (std::size_t i = first[static_cast<std::size_t>(r)]; i < first[static_cast<std::size_t>(r) + 1]; ++i) {
      const Item& item = items[by_top[i]];
      int s = strokes;
      if (idle.empty()) {
        ++strokes;
        later.push_back(kNone);
      } else {
        s = idle.back();
        idle.pop_back();
      }
      stroke_of[by_top[i]] = s;
      later[static_cast<std::size_t>(s)] = ending[static_cast<std::size_t>(item.bottom)];
      ending[static_cast<std::size_t>(item.bottom)] = s;
    }
  }
  // Then the long edges stroke by stroke, each stroke's in order of their top rows.
  std::vector<std::size_t> sizes(static_cast<std::size_t>(strokes), 0);
  for (std::size_t i : by_top) ++sizes[static_cast<std::size_t>(stroke_of[i])];
  std::vector<std::size_t> next(sizes.size());
  std::size_t end = plan.edges.size();
  for (std::size_t s = 0; s < sizes.size(); ++s) {
    next[s] = end;
    end += sizes[s];
    plan.ends.push_back(end);
  }
  plan.edges.resize(end);
  for (std::size_t i : by_top) plan.edges[next[static_cast<std::size_t>(stroke_of[i])]++] = edges[items[i].edge];
  return plan;
}

namespace {

// The planned edges, thin and black, with butt ends: at 0.6 px a round cap adds no ink that reads
// (the edges meeting at a vertex cover it) but its arc's vertices are a good part of cairo's
// stroking and scan conversion of a dense mesh. A band strokes the planned strokes' edges in its
// rows, so that a banded picture is pixel for pixel the whole one.
void draw_edges(Canvas& canvas, const Mesh& mesh, const EdgeStrokes& plan) {
  const double edge_width = 0.6;
  StrokeBatch lines(canvas, colours::kBlack, edge_width, CAIRO_LINE_CAP_BUTT);
  InterruptPoll poll(65536);
  std::size_t k = 0;
  for (std::size_t end : plan.ends) {
    for (; k < end; ++k) {
      poll.tick();
      const Vec2 a = mesh.points[static_cast<std::size_t>(plan.edges[k].first)];
      const Vec2 b = mesh.points[static_cast<std::size_t>(plan.edges[k].second)];
      Box box;
      box.add(a);
      box.add(b);
      if (canvas.visible(box))
        lines.segment(a, b);
      else
        lines.skip();  // in another band
    }
    lines.flush();
  }
}

}  // namespace

ColourBarBox draw_colour_ramp_bar(Canvas& canvas) {
  cairo_t* cr = canvas.context();
  cairo_reset_clip(cr);
  ColourBarBox b{canvas.plot_right() + 30, canvas.plot_top() + 40, 30, std::max(60.0, canvas.plot_height() - 80)};
  // Drawn as thin bands so that the SVG needs no gradient support to look right.
  const int bands = 128;
  for (int k = 0; k < bands; ++k) {
    const Rgb c = colour_ramp(1.0 - (k + 0.5) / bands);
    cairo_set_source_rgb(cr, c.r, c.g, c.b);
    cairo_rectangle(cr, b.x, b.top + b.height * k / bands, b.width, b.height / bands + 0.5);
    cairo_fill(cr);
  }
  cairo_set_source_rgb(cr, 0, 0, 0);
  cairo_set_line_width(cr, 1);
  cairo_rectangle(cr, b.x, b.top, b.width, b.height);
  cairo_stroke(cr);
  return b;
}

Rgb colour_ramp(double t) {
  if (!std::isfinite(t)) return kNoValue;
  t = std::clamp(t, 0.0, 1.0) * (kViridis.size() - 1);
  const auto k = std::min<std::size_t>(static_cast<std::size_t>(t), kViridis.size() - 2);
  const double f = t - static_cast<double>(k);
  const Rgb& a = kViridis[k];
  const Rgb& b = kViridis[k + 1];
  return {a.r + f * (b.r - a.r), a.g + f * (b.g - a.g), a.b + f * (b.b - a.b)};
}

std::optional<CloseUp> dense_mesh_close_up(const Mesh& mesh, const Box& window, int long_side) {
  if (mesh.triangles.empty()) return std::nullopt;
  const double side = std::max(window.width(), window.height());
  const double min_edge_world = kMinEdgePixels * side / long_side;
  // The short edges and the worst triangle (the first with the smallest angle) of each block of
  // triangles, on several threads; taken together in block order they are one loop's.
  struct Part {
    std::size_t short_edges = 0;
    std::size_t worst = 0;
    double worst_angle = INFINITY;
  };
  constexpr std::size_t kBlock = 16384;
  std::vector<Part> parts((mesh.triangles.size() + kBlock - 1) / kBlock);
  parallel_for(
      parts.size(),
      [&](std::size_t k) {
        Part& part = parts[k];
        for (std::size_t t = k * kBlock; t < std::min(mesh.triangles.size(), (k + 1) * kBlock); ++t) {
          const auto& tri = mesh.triangles[t];
          const Vec2 a = mesh.points[tri[0]], b = mesh.points[tri[1]], c = mesh.points[tri[2]];
          part.short_edges += static_cast<std::size_t>(!shown(a, b, min_edge_world)) +
                              static_cast<std::size_t>(!shown(b, c, min_edge_world)) +
                              static_cast<std::size_t>(!shown(c, a, min_edge_world));
          const double angle = triangle_shape(a, b, c).min_angle;
          if (angle < part.worst_angle) {
            part.worst_angle = angle;
            part.worst = t;
          }
        }
      },
      1);
  std::size_t short_edges = 0;
  std::size_t worst = 0;
  double worst_angle = INFINITY;
  for (const Part& part : parts) {
    short_edges += part.short_edges;
    if (part.worst_angle < worst_angle) {
      worst_angle = part.worst_angle;
      worst = part.worst;
    }
  }
  if (2 * short_edges <= 3 * mesh.triangles.size()) return std::nullopt;
  const auto& tri = mesh.triangles[worst];
  const Vec2 a = mesh.points[tri[0]], b = mesh.points[tri[1]], c = mesh.points[tri[2]];
  const double longest = std::max({dist(a, b), dist(b, c), dist(c, a)});
  // A worst triangle among the largest (a graded far field's) would give a square nearly as wide as
  // mesh.png's window: no close-up.
  if (kCloseUpEdges * longest > kCloseUpLargest * side) return std::nullopt;
  const double half = 0.5 * kCloseUpEdges * longest;
  const Vec2 worst_centre{(a.x + b.x + c.x) / 3.0, (a.y + b.y + c.y) / 3.0};
  // Half-way towards the mean of the points in the square: a triangle on the domain's edge keeps the
  // mesh beside it in view instead of the empty outside (the triangle stays within a quarter side of
  // the centre).
  Vec2 sum{0, 0};
  std::size_t inside = 0;
  for (const Vec2& p : mesh.points) {
    if (std::abs(p.x - worst_centre.x) <= half && std::abs(p.y - worst_centre.y) <= half) {
      sum = sum + p;
      ++inside;
    }
  }
  const Vec2 mean = inside > 0 ? sum * (1.0 / static_cast<double>(inside)) : worst_centre;
  const Vec2 centre = worst_centre + (mean - worst_centre) * 0.5;
  CloseUp close_up;
  close_up.window.add({centre.x - half, centre.y - half});
  close_up.window.add({centre.x + half, centre.y + half});
  close_up.min_angle = worst_angle;
  return close_up;
}

Box default_mesh_window(const Mesh& mesh) {
  Box extents;
  for (const Vec2& p : mesh.points) extents.add(p);
  return padded_window(extents);
}

void write_mesh_picture(const std::filesystem::path& path, const Mesh& mesh, const MeshPictureOptions& options) {
  const std::vector<double>* values = options.triangle_values;
  check_picture_inputs(path, mesh, values);
  if (values != nullptr && options.fill_regions)
    throw Error(fmt::format("mesh picture '{}': a fill by value and by region both asked for", path.string()));
  const std::pair<double, double> range = ramp_range(values, options);
  const double lo = range.first, hi = range.second;
  const RegionFill regions = options.fill_regions ? region_fill(mesh) : RegionFill{};
  const FillGroups value_groups = values != nullptr ? value_fill_groups(*values, lo, hi) : FillGroups{};
  const std::vector<std::pair<int, int>> interfaces = region_interfaces(mesh);
  CanvasOptions layout;
  layout.window = options.window ? *options.window : default_mesh_window(mesh);
  layout.long_side = options.long_side;
  layout.side_width = values != nullptr ? kMeshBarBand : options.fill_regions ? region_legend_width(regions) : 0;
  layout.grey = values == nullptr && !options.fill_regions;  // black edges, the grey shade, a black title

  // Each edge once (an interior edge belongs to two triangles).
  const std::vector<std::pair<int, int>> edges = unique_edges(mesh);

  // The edges' strokes, planned by the first band to start (every band's canvas maps the world to
  // the same pixels).
  std::once_flag planned;
  EdgeStrokes strokes;

  // Drawn in bands on several threads (PNG; render_picture): everything below only reads the mesh.
  render_picture(
      path, layout,
      [&](Canvas& canvas) {
        const double min_edge_world = kMinEdgePixels / canvas.scale();
        std::call_once(planned, [&] { strokes = plan_edge_strokes(canvas, mesh, edges); });
        // Value or region fills first, then the edges on top of them.
        if (options.fill_regions)
          draw_fill_groups(canvas, mesh, regions.groups);
        else if (values == nullptr)
          draw_dense_shade(canvas, mesh, min_edge_world);
        else
          draw_fill_groups_seamless(canvas, mesh, value_groups);
        draw_edges(canvas, mesh, strokes);
        const std::size_t skipped = strokes.too_short;
        {
          StrokeBatch boundary(canvas, colours::kBlack, 2.0);
          for (const BoundaryEdge& e : mesh.boundary_edges) boundary.segment(mesh.points[e.a], mesh.points[e.b]);
          for (const auto& [a, b] : interfaces)
            boundary.segment(mesh.points[static_cast<std::size_t>(a)], mesh.points[static_cast<std::size_t>(b)]);
        }
        canvas.title(
            fmt::format("{}   {} points, {} triangles{}", options.title, mesh.points.size(), mesh.triangles.size(),
                        skipped > 0 ? fmt::format(" (edges under {} px not drawn)", kMinEdgePixels) : std::string()));
        if (values != nullptr) {
          draw_colour_bar(canvas, std::isfinite(lo) ? lo : 0.0, std::isfinite(hi) ? hi : 0.0, options.value_label);
        }
        if (options.fill_regions) draw_region_legend(canvas, regions);
      },
      options.bands);
}

}  // namespace pdmesh
