// UGAWG measures in a metric (metric_quality.hpp).
#include "mesh/metric_quality.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "spacing/metric_complexity.hpp"
#include "spacing/metric_field.hpp"
#include "spacing/metric_gradation.hpp"

namespace pdmesh {

std::vector<double> metric_edge_lengths(const std::vector<Vec2>& points, const std::vector<std::array<int, 2>>& edges,
                                        const std::vector<Metric>& metrics) {
  std::vector<double> l(edges.size());
  for (std::size_t i = 0; i < edges.size(); ++i) {
    const auto [a, b] = edges[i];
    l[i] = edge_length(metrics[a], metrics[b], points[b] - points[a]);
  }
  return l;
}

std::vector<double> metric_qualities(const std::vector<Vec2>& points, const std::vector<std::array<int, 3>>& triangles,
                                     const std::vector<Metric>& metrics) {
  std::vector<double> q(triangles.size());
  for (std::size_t i = 0; i < triangles.size(); ++i) {
    const auto& t = triangles[i];
    // The corner of largest det; the first on ties.
    int pick = t[0];
    for (int k = 1; k < 3; ++k)
      if (metrics[t[k]].det() > metrics[pick].det()) pick = t[k];
    const Metric& m = metrics[pick];
    const Vec2 a = points[t[0]], b = points[t[1]], c = points[t[2]];
    const double area = 0.5 * ((b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x));
    const double sum_l2 = m.quad(b - a) + m.quad(c - b) + m.quad(a - c);
    q[i] = 4.0 * std::sqrt(3.0) * area * std::sqrt(m.det()) / sum_l2;
  }
  return q;
}

MetricQualitySummary metric_quality(const Mesh& mesh, const std::vector<Metric>& metrics, double complexity) {
  MetricQualitySummary s;
  s.vertices = mesh.points.size();
  s.triangles = mesh.triangles.size();
  const auto edges = triangle_edges(mesh.triangles);
  s.edges = edges.size();
  const std::vector<double> l = metric_edge_lengths(mesh.points, edges, metrics);
  const std::vector<double> q = metric_qualities(mesh.points, mesh.triangles, metrics);
  if (!l.empty()) {
    std::size_t inside = 0;
    s.length_min = std::numeric_limits<double>::infinity();
    s.length_max = -std::numeric_limits<double>::infinity();
    for (double x : l) {
      inside += (x >= kMetricWindowLo && x <= kMetricWindowHi) ? 1 : 0;
      s.length_min = std::min(s.length_min, x);
      s.length_max = std::max(s.length_max, x);
    }
    s.window_percent = 100.0 * static_cast<double>(inside) / static_cast<double>(l.size());
  }
  if (!q.empty()) {
    s.q_min = std::numeric_limits<double>::infinity();
    double sum = 0.0;
    std::size_t below = 0;
    for (double x : q) {
      s.q_min = std::min(s.q_min, x);
      sum += x;
      below += x < 0.3 ? 1 : 0;
      // Bin edges k/10 as metric.py writes them (0.1, 0.2, ...), so a Q on an edge falls on its side.
      static constexpr std::array<double, 9> kEdges{0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9};
      const std::size_t bin =
          static_cast<std::size_t>(std::upper_bound(kEdges.begin(), kEdges.end(), x) - kEdges.begin());
      ++s.q_histogram[bin];
    }
    s.q_mean = sum / static_cast<double>(q.size());
    s.q_below_0_3_percent = 100.0 * static_cast<double>(below) / static_cast<double>(q.size());
  }
  if (complexity > 0.0) {
    s.complexity = complexity;
    s.ideal_triangles = ideal_triangles(complexity);
    s.n_over_ideal = static_cast<double>(s.triangles) / s.ideal_triangles;
  }
  return s;
}

MetricQualitySummary metric_quality(const Mesh& mesh, const MetricField& field) {
  std::vector<Metric> metrics;
  metrics.reserve(mesh.points.size());
  for (const Vec2& p : mesh.points) metrics.push_back(field.at(p));
  return metric_quality(mesh, metrics, complexity_on_mesh(mesh.points, mesh.triangles, metrics));
}

}  // namespace pdmesh
