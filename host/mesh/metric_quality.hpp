// The anisotropic measures of a mesh in a metric given at its points (the Unstructured Grid
// Adaptation Working Group's, 2-D), the same formulas as tools/eval/pdmesh_eval/metric.py:
// metric edge lengths and the share in the unit-mesh window [1/√2, √2], the mean-ratio quality
// Q = 4√3 |K| sqrt(det M) / Σ l²_M (M the corner metric of largest det; 1 for a triangle equilateral
// in M, <= 0 for an inverted one), and the element count against the ideal 4C/√3.
// `pdmesh mesh` and `pdmesh quality` report them for a metric run: docs/metric-fields.md.
#pragma once
#include <array>
#include <cmath>
#include <cstddef>
#include <vector>

#include "core/vec2.hpp"
#include "mesh/mesh.hpp"
#include "spacing/metric.hpp"

namespace pdmesh {

// The unit-mesh window of metric edge lengths.
inline const double kMetricWindowLo = 1.0 / std::sqrt(2.0);
inline const double kMetricWindowHi = std::sqrt(2.0);

// Q's histogram: bin 0 is Q < 0.1, bin k (1..8) is [k/10, (k+1)/10), bin 9 is Q >= 0.9 (metric.py's Q_BINS).
inline constexpr std::size_t kMetricQualityBins = 10;

struct MetricQualitySummary {
  std::size_t vertices = 0;
  std::size_t triangles = 0;
  std::size_t edges = 0;
  double window_percent = 0.0;  // edges with L in [1/√2, √2]
  double length_min = 0.0;
  double length_max = 0.0;
  double q_min = 0.0;
  double q_mean = 0.0;
  double q_below_0_3_percent = 0.0;
  std::array<std::size_t, kMetricQualityBins> q_histogram{};
  // With a complexity C > 0 given: 4C/√3 and triangles / (4C/√3); else 0.
  double complexity = 0.0;
  double ideal_triangles = 0.0;
  double n_over_ideal = 0.0;
};

// The metric length (spacing/metric.hpp's edge_length) of each edge {a, b}, v = points[b] - points[a].
std::vector<double> metric_edge_lengths(const std::vector<Vec2>& points, const std::vector<std::array<int, 2>>& edges,
                                        const std::vector<Metric>& metrics);

// Q of each triangle, in triangle order.
std::vector<double> metric_qualities(const std::vector<Vec2>& points, const std::vector<std::array<int, 3>>& triangles,
                                     const std::vector<Metric>& metrics);

// Every measure of `mesh` with metrics[i] at mesh.points[i] (sizes must match); the edges are the
// triangles' unique edges. complexity <= 0 leaves the element-count figures at 0.
MetricQualitySummary metric_quality(const Mesh& mesh, const std::vector<Metric>& metrics, double complexity = 0.0);

class MetricField;
// How `mesh` honours a case's metric field: every measure with the field's metric at each point and
// the complexity by the P1 rule on the mesh (spacing/metric_complexity's complexity_on_mesh).
MetricQualitySummary metric_quality(const Mesh& mesh, const MetricField& field);

}  // namespace pdmesh
