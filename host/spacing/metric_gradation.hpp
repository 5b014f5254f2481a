// Metric gradation on a graph of points: the metrics at the points shrunk (sizes made smaller, never
// larger) until along every edge the metric at one end grows into the other's no faster than the
// rate beta allows (spacing/metric.hpp's span_metric and edge_gradation). The anisotropic counterpart of
// spacing/gradation's isotropic limit, in metric space or mixed (Alauzet & Frazza).
#pragma once
#include <array>
#include <vector>

#include "core/vec2.hpp"
#include "spacing/metric.hpp"

namespace pdmesh {

struct MetricGradationOptions {
  double beta = 1.5;  // the largest size ratio per unit of metric length (> 1)
  // 0: metric-space growth (the shape of a metric is kept as it spreads, which is what lets a
  // stretched layer's metric widen the layer rather than round it off); 1: physical-space growth;
  // Alauzet & Frazza's mixed form uses 1/8.
  double t = 0.0;
  int max_sweeps = 100;
  double tolerance = 1.01;  // an edge counts as limited when its gradation is <= tolerance * beta
};

struct MetricGradationResult {
  int sweeps = 0;              // sweeps over the edges that changed something
  bool converged = false;      // the last sweep changed nothing
  double max_gradation = 1.0;  // over the edges after the last sweep
};

// Limits `metrics` (one per point) in place. Each sweep visits the edges (in order and in reverse order
// by turns) and intersects each end's metric with the other end's span along the edge, where the
// edge's gradation exceeds tolerance * beta; intersection only adds, so the sweeps converge.
// Deterministic: the edge order decides the result. Throws InputError naming the option for beta <= 1, t outside [0,
// 1], or a tolerance < 1; edges must index points.
MetricGradationResult limit_metric_gradation(const std::vector<Vec2>& points,
                                             const std::vector<std::array<int, 2>>& edges, std::vector<Metric>& metrics,
                                             const MetricGradationOptions& options);

// The unique edges (smaller index first, sorted) of triangles given by point indices.
std::vector<std::array<int, 2>> triangle_edges(const std::vector<std::array<int, 3>>& triangles);

}  // namespace pdmesh
