// Metric gradation by sweeps of span-and-intersect over the edges (metric_gradation.hpp).
#include "spacing/metric_gradation.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "core/errors.hpp"

namespace pdmesh {

namespace {

// Whether b differs from a by more than rounding would explain, relative to a's size.
bool moved(const Metric& a, const Metric& b) {
  const double scale = std::fabs(a.m11) + std::fabs(a.m22);
  return std::fabs(a.m11 - b.m11) + 2.0 * std::fabs(a.m12 - b.m12) + std::fabs(a.m22 - b.m22) > 1e-12 * scale;
}

}  // namespace

MetricGradationResult limit_metric_gradation(const std::vector<Vec2>& points,
                                             const std::vector<std::array<int, 2>>& edges, std::vector<Metric>& metrics,
                                             const MetricGradationOptions& options) {
  if (!(options.beta > 1.0) || !std::isfinite(options.beta))
    throw InputError(fmt::format("metric gradation: beta = {} must be a finite number > 1", options.beta));
  if (!(options.t >= 0.0 && options.t <= 1.0))
    throw InputError(fmt::format("metric gradation: t = {} must lie in [0, 1]", options.t));
  if (!(options.tolerance >= 1.0) || !std::isfinite(options.tolerance))
    throw InputError(fmt::format("metric gradation: tolerance = {} must be a finite number >= 1", options.tolerance));
  const double limit = options.tolerance * options.beta;
  MetricGradationResult result;
  for (int sweep = 0; sweep < options.max_sweeps; ++sweep) {
    bool changed = false;
    // Forward and backward in turn: a sweep carries a small metric along the edge order in one
    // pass, and the next carries it back against that order.
    const bool backward = sweep % 2 == 1;
    for (std::size_t k = 0; k < edges.size(); ++k) {
      const auto& e = edges[backward ? edges.size() - 1 - k : k];
      const Vec2 v = points[e[1]] - points[e[0]];
      Metric& ma = metrics[e[0]];
      Metric& mb = metrics[e[1]];
      if (edge_gradation(ma, mb, v) <= limit) continue;
      // Each end takes in the other's span; where one metric dominates the other, only the smaller
      // one changes. An intersection that moves nothing (the mixed span can leave an edge above
      // the limit that no further sweep improves) does not count as a change.
      const Metric from_a = span_metric(ma, v, options.beta, options.t);
      const Metric from_b = span_metric(mb, v, options.beta, options.t);
      const Metric new_b = intersect(mb, from_a);
      const Metric new_a = intersect(ma, from_b);
      changed = changed || moved(ma, new_a) || moved(mb, new_b);
      ma = new_a;
      mb = new_b;
    }
    if (!changed) {
      result.converged = true;
      break;
    }
    ++result.sweeps;
  }
  for (const auto& e : edges)
    result.max_gradation =
        std::max(result.max_gradation, edge_gradation(metrics[e[0]], metrics[e[1]], points[e[1]] - points[e[0]]));
  return result;
}

std::vector<std::array<int, 2>> triangle_edges(const std::vector<std::array<int, 3>>& triangles) {
  std::vector<std::array<int, 2>> edges;
  edges.reserve(3 * triangles.size());
  for (const auto& t : triangles)
    for (int k = 0; k < 3; ++k) {
      const int a = t[k], b = t[(k + 1) % 3];
      edges.push_back({std::min(a, b), std::max(a, b)});
    }
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  return edges;
}

}  // namespace pdmesh
