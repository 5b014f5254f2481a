// Region fills of mesh pictures: palette, legend entries, interfaces, and their drawing.
#include "render/region_fill.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <string_view>
#include <fmt/format.h>

#include "core/errors.hpp"
#include "io/mesh_io_common.hpp"

namespace pdmesh {

namespace {

constexpr std::array<Rgb, 7> kOkabeIto = {{{0.902, 0.624, 0.0},
                                           {0.337, 0.706, 0.914},
                                           {0.0, 0.620, 0.451},
                                           {0.941, 0.894, 0.259},
                                           {0.0, 0.447, 0.698},
                                           {0.835, 0.369, 0.0},
                                           {0.800, 0.475, 0.655}}};

constexpr double kLegendFont = 14;
constexpr double kLegendRow = 22;
constexpr double kSwatch = 16;
constexpr double kLegendLeft = 20;  // from the plot's right edge
constexpr double kSwatchGap = 8;
constexpr std::size_t kLabelChars = 40;  // longer labels are cut, so that the band stays narrow

bool in_a_region(double attribute) { return std::isfinite(attribute) && attribute != 0.0; }

// The label as drawn: at most kLabelChars bytes, cut at a UTF-8 character boundary, with "...".
std::string shown_label(const std::string& label) {
  if (label.size() <= kLabelChars) return label;
  std::size_t cut = kLabelChars;
  while (cut > 0 && (static_cast<unsigned char>(label[cut]) & 0xC0) == 0x80) --cut;
  return label.substr(0, cut) + "...";
}

// Legend rows below the caption that fit the plot's height; at least one.
std::size_t legend_rows(double plot_height) {
  return static_cast<std::size_t>(std::max(1.0, std::floor((plot_height - 2 * kLegendRow) / kLegendRow)));
}

std::string more_label(std::size_t more) { return fmt::format("... and {} more", more); }

std::uint64_t edge_key(int a, int b) {
  const auto lo = static_cast<std::uint64_t>(static_cast<std::uint32_t>(std::min(a, b)));
  const auto hi = static_cast<std::uint64_t>(static_cast<std::uint32_t>(std::max(a, b)));
  return (lo << 32) | hi;
}

}  // namespace

std::size_t region_palette_size() { return kOkabeIto.size(); }

Rgb region_palette_colour(std::size_t k) { return kOkabeIto[k % kOkabeIto.size()]; }

RegionFill region_fill(const Mesh& mesh) {
  const std::size_t n = mesh.triangles.size();
  if (!mesh.region.empty() && mesh.region.size() != n) {
    throw Error(fmt::format("mesh picture: {} region attributes for {} triangles", mesh.region.size(), n));
  }
  std::vector<double> attributes;
  for (double a : mesh.region)
    if (in_a_region(a)) attributes.push_back(a);
  std::sort(attributes.begin(), attributes.end());
  attributes.erase(std::unique(attributes.begin(), attributes.end()), attributes.end());
  RegionFill fill;
  for (std::size_t k = 0; k < attributes.size(); ++k) {
    RegionLegendEntry e;
    e.attribute = attributes[k];
    e.colour = region_palette_colour(k);
    const std::string_view name = region_name(mesh, attributes[k]);
    e.label = name.empty() ? fmt::format("attribute {}", attributes[k]) : std::string(name);
    fill.entries.push_back(std::move(e));
  }
  // Each triangle's entry: its attribute's, or the "no region" entry after them.
  const std::size_t none = attributes.size();
  std::vector<std::uint32_t> entry_of(n, static_cast<std::uint32_t>(none));
  for (std::size_t t = 0; t < mesh.region.size(); ++t) {
    if (!in_a_region(mesh.region[t])) continue;
    const auto it = std::lower_bound(attributes.begin(), attributes.end(), mesh.region[t]);
    entry_of[t] = static_cast<std::uint32_t>(it - attributes.begin());
  }
  std::vector<std::size_t> counts(none + 1, 0);
  for (std::uint32_t e : entry_of) ++counts[e];
  if (counts[none] > 0 || fill.entries.empty()) {
    RegionLegendEntry e;
    e.label = "no region";
    e.colour = kNoRegion;
    fill.entries.push_back(std::move(e));
  }
  std::vector<Rgb> colours;
  for (std::size_t k = 0; k < fill.entries.size(); ++k) {
    fill.entries[k].triangles = counts[k];
    colours.push_back(fill.entries[k].colour);
  }
  fill.groups = group_fills(entry_of, std::move(colours));
  return fill;
}

std::vector<std::pair<int, int>> region_interfaces(const Mesh& mesh) {
  std::vector<std::pair<int, int>> out;
  if (mesh.region.size() != mesh.triangles.size() || mesh.triangles.empty()) return out;
  const double first = mesh.region[0];
  const bool one_region = std::all_of(mesh.region.begin(), mesh.region.end(),
                                      [&](double a) { return a == first || (!in_a_region(a) && !in_a_region(first)); });
  if (one_region) return out;
  // Every triangle's edges by key, with the triangle's attribute (non-finite ones as 0, as the
  // fills show them): an edge whose two entries differ lies between regions.
  std::vector<std::pair<std::uint64_t, double>> sides;
  sides.reserve(3 * mesh.triangles.size());
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const auto& tri = mesh.triangles[t];
    const double a = in_a_region(mesh.region[t]) ? mesh.region[t] : 0.0;
    for (int k = 0; k < 3; ++k) sides.emplace_back(edge_key(tri[k], tri[(k + 1) % 3]), a);
  }
  std::sort(sides.begin(), sides.end());
  std::vector<std::uint64_t> boundary;
  boundary.reserve(mesh.boundary_edges.size());
  for (const BoundaryEdge& e : mesh.boundary_edges) boundary.push_back(edge_key(e.a, e.b));
  std::sort(boundary.begin(), boundary.end());
  for (std::size_t i = 0; i + 1 < sides.size();) {
    std::size_t j = i + 1;
    while (j < sides.size() && sides[j].first == sides[i].first) ++j;
    // Sorted by attribute within a key: the run's ends differ when any two of its sides do.
    if (sides[j - 1].second != sides[i].second && !std::binary_search(boundary.begin(), boundary.end(), sides[i].first))
      out.emplace_back(static_cast<int>(sides[i].first >> 32), static_cast<int>(sides[i].first & 0xFFFFFFFFu));
    i = j;
  }
  return out;
}

int region_legend_width(const RegionFill& fill) {
  // The labels measured at the legend's font on a scratch surface (the canvas, whose width this
  // decides, does not exist yet).
  cairo_surface_t* scratch = cairo_image_surface_create(CAIRO_FORMAT_A8, 1, 1);
  cairo_t* cr = cairo_create(scratch);
  cairo_select_font_face(cr, "sans-serif", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
  cairo_set_font_size(cr, kLegendFont);
  double widest = 0;
  const auto measure = [&](const std::string& s) {
    cairo_text_extents_t extents;
    cairo_text_extents(cr, s.c_str(), &extents);
    widest = std::max(widest, extents.x_advance);
  };
  measure("region");
  for (const RegionLegendEntry& e : fill.entries) measure(shown_label(e.label));
  measure(more_label(fill.entries.size()));
  cairo_destroy(cr);
  cairo_surface_destroy(scratch);
  return static_cast<int>(std::ceil(kLegendLeft + kSwatch + kSwatchGap + widest + 16));
}

void draw_region_legend(Canvas& canvas, const RegionFill& fill) {
  cairo_t* cr = canvas.context();
  cairo_reset_clip(cr);
  const double x = canvas.plot_right() + kLegendLeft;
  double y = canvas.plot_top() + kLegendRow;
  canvas.text(x, y, "region", kLegendFont, colours::kBlack);
  const std::size_t rows = legend_rows(canvas.plot_height());
  // All entries when they fit; else rows - 1 of them and a row saying how many more.
  const std::size_t shown = fill.entries.size() <= rows ? fill.entries.size() : rows - 1;
  for (std::size_t k = 0; k < shown; ++k) {
    const RegionLegendEntry& e = fill.entries[k];
    y += kLegendRow;
    const double top = y - kSwatch + 3;
    cairo_set_source_rgb(cr, e.colour.r, e.colour.g, e.colour.b);
    cairo_rectangle(cr, x, top, kSwatch, kSwatch);
    cairo_fill_preserve(cr);
    cairo_set_source_rgb(cr, 0, 0, 0);
    cairo_set_line_width(cr, 1);
    cairo_stroke(cr);
    canvas.text(x + kSwatch + kSwatchGap, y, shown_label(e.label), kLegendFont, colours::kBlack);
  }
  if (shown < fill.entries.size())
    canvas.text(x, y + kLegendRow, more_label(fill.entries.size() - shown), kLegendFont, colours::kBlack);
}

}  // namespace pdmesh
