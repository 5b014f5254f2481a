// measure_layers(): the layer measures of layer_measures.hpp.
#include "layers/layer_measures.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "core/predicates.hpp"

namespace pdmesh {

namespace {

// The q-quantile of the values (nearest rank); 0 for none.
double quantile(std::vector<double> v, double q) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const auto k = static_cast<std::size_t>(std::ceil(q * static_cast<double>(v.size())));
  return v[std::min(v.size() - 1, k == 0 ? 0 : k - 1)];
}

double height_over(Vec2 a, Vec2 b, Vec2 x) { return std::abs(cross(b - a, x - a)) / norm(b - a); }

}  // namespace

void add_cell_angles(const std::vector<Vec2>& x, const std::array<int, 4>& v, CellAngles& out) {
  const int k = v[3] < 0 ? 3 : 4;
  ++out.cells;
  (k == 3 ? out.triangles : out.quads) += 1;
  bool inverted = false;
  for (int i = 0; i < k; ++i) {
    const Vec2 p = x[v[(i + k - 1) % k]], c = x[v[i]], n = x[v[(i + 1) % k]];
    if (orient2d(p, c, n) <= 0.0) inverted = true;
    double a = std::atan2(cross(n - c, p - c), dot(n - c, p - c));
    if (a < 0) a += 2.0 * std::numbers::pi;
    const double deg = a * 180.0 / std::numbers::pi;
    out.max_angle_deg = std::max(out.max_angle_deg, deg);
    if (deg > 150.0) ++out.angles_above_150;
  }
  out.inverted_cells += inverted ? 1 : 0;
}

LayerMeasures measure_layers(const LayerMesh& mesh, double first_height, const CoreSpacing& core_spacing) {
  LayerMeasures out;
  out.nodes = static_cast<int>(mesh.nodes.size());
  out.cells = static_cast<int>(mesh.cells.size());
  out.fan_sizes = mesh.fan_sizes;
  const auto& x = mesh.nodes;
  int within = 0;
  CellAngles angles;
  for (const LayerCell& cell : mesh.cells) {
    const int k = cell.triangle() ? 3 : 4;
    add_cell_angles(x, cell.v, angles);
    // A wall cell: an edge between two wall nodes; its other corners' heights over that edge.
    for (int i = 0; i < k; ++i) {
      const int a = cell.v[i], b = cell.v[(i + 1) % k];
      if (a >= mesh.wall_nodes || b >= mesh.wall_nodes || a == b) continue;
      ++out.wall_cells;
      double worst = 0.0;
      for (int j = 0; j < k; ++j) {
        const int c = cell.v[j];
        if (c < mesh.wall_nodes) continue;
        worst = std::max(worst, std::abs(height_over(x[a], x[b], x[c]) / first_height - 1.0));
      }
      out.first_height_max_error = std::max(out.first_height_max_error, worst);
      within += worst <= 0.02 ? 1 : 0;
      break;
    }
  }
  out.quads = angles.quads;
  out.triangles = angles.triangles;
  out.max_angle_deg = angles.max_angle_deg;
  out.angles_above_150 = angles.angles_above_150;
  out.inverted_cells = angles.inverted_cells;
  out.first_height_within_2pct = out.wall_cells ? static_cast<double>(within) / out.wall_cells : 0.0;

  std::vector<double> inside, junction;
  out.min_thickness = std::numeric_limits<double>::infinity();
  for (const LayerRay& ray : mesh.rays) {
    const int n = static_cast<int>(ray.nodes.size()) - 1;
    out.max_layers = std::max(out.max_layers, n);
    out.min_thickness = std::min(out.min_thickness, ray.thickness);
    out.max_thickness = std::max(out.max_thickness, ray.thickness);
    double last = 0.0;
    for (int k = 1; k <= n; ++k) {
      const double t = dist(x[ray.nodes[k - 1]], x[ray.nodes[k]]) * ray.correction;
      if (k > 1) inside.push_back(t / last);
      last = t;
    }
    if (n >= 1 && core_spacing && !ray.merged) junction.push_back(core_spacing(x[ray.nodes.back()]) / last);
  }
  if (mesh.rays.empty()) out.min_thickness = 0.0;
  out.growth_median = quantile(inside, 0.5);
  out.growth_p95 = quantile(inside, 0.95);
  out.growth_max = inside.empty() ? 0.0 : *std::max_element(inside.begin(), inside.end());
  out.junction_median = quantile(junction, 0.5);
  out.junction_p95 = quantile(junction, 0.95);
  out.junction_max = junction.empty() ? 0.0 : *std::max_element(junction.begin(), junction.end());
  std::vector<double> both = inside;
  both.insert(both.end(), junction.begin(), junction.end());
  out.growth_with_junction_p95 = quantile(both, 0.95);
  out.growth_with_junction_max = std::max(out.growth_max, out.junction_max);

  int curves = 0;
  for (const LayerRay& ray : mesh.rays) curves = std::max(curves, ray.curve + 1);
  out.jump_by_curve.assign(curves, 1.0);
  for (std::size_t c = 0; c + 1 < mesh.chain_ray_begin.size(); ++c) {
    const int b = mesh.chain_ray_begin[c], e = mesh.chain_ray_begin[c + 1], n = e - b;
    const bool closed = mesh.chain_closed[c] != 0;
    for (int k = 0; k < (closed ? n : n - 1); ++k) {
      const LayerRay& ra = mesh.rays[b + k];
      const LayerRay& rb = mesh.rays[b + (k + 1) % n];
      if (ra.wall_node == rb.wall_node) continue;
      const double lo = std::min(ra.thickness, rb.thickness), hi = std::max(ra.thickness, rb.thickness);
      const double jump = hi == 0.0 ? 1.0 : (lo == 0.0 ? std::numeric_limits<double>::infinity() : hi / lo);
      out.max_thickness_jump = std::max(out.max_thickness_jump, jump);
      for (const int curve : {ra.curve, rb.curve}) out.jump_by_curve[curve] = std::max(out.jump_by_curve[curve], jump);
    }
  }
  return out;
}

std::string format_layer_measures(const LayerMeasures& m, const std::vector<std::string>& curve_names) {
  std::string s;
  s += fmt::format("nodes {}  cells {} ({} quads, {} triangles)  inverted {}\n", m.nodes, m.cells, m.quads, m.triangles,
                   m.inverted_cells);
  s += fmt::format("wall cells {}: {:.2f} % within +-2 % of h1, max error {:.3g} %\n", m.wall_cells,
                   100.0 * m.first_height_within_2pct, 100.0 * m.first_height_max_error);
  s += fmt::format("growth inside: median {:.4f} p95 {:.4f} max {:.4f}\n", m.growth_median, m.growth_p95, m.growth_max);
  s += fmt::format("junction (core q / last layer): median {:.3f} p95 {:.3f} max {:.3f}\n", m.junction_median,
                   m.junction_p95, m.junction_max);
  s += fmt::format("growth incl. junction: p95 {:.4f} max {:.4f}\n", m.growth_with_junction_p95,
                   m.growth_with_junction_max);
  s += fmt::format("max angle {:.1f} deg, {} angles above 150 deg\n", m.max_angle_deg, m.angles_above_150);
  s += fmt::format("fans {} (elements: {})\n", m.fan_sizes.size(), fmt::join(m.fan_sizes, " "));
  s += fmt::format("layers max {}  thickness {:.4g} .. {:.4g}  max jump between neighbours {:.3f}\n", m.max_layers,
                   m.min_thickness, m.max_thickness, m.max_thickness_jump);
  for (std::size_t c = 0; c < m.jump_by_curve.size(); ++c)
    if (m.jump_by_curve[c] > 1.0)
      s += fmt::format("  jump on {}: {:.3f}\n", c < curve_names.size() ? curve_names[c] : fmt::format("curve{}", c),
                       m.jump_by_curve[c]);
  return s;
}

}  // namespace pdmesh
