// Delaunay triangulation in a metric field (anisotropic Delaunay): Lawson flips of a triangulation
// whose flip criterion is the in-circle test in the local metric of each quadrilateral, the
// log-Euclidean mean of its four vertices' metrics. The isotropic triangulation (mesh/delaunay,
// mesh/constrain) is its start and is not changed by it: a run without a metric never comes here.
// See docs/metric-fields.md, "Delaunay in the metric".
#pragma once
#include <cstddef>
#include <vector>

#include "core/vec2.hpp"
#include "mesh/delaunay.hpp"
#include "spacing/metric.hpp"

namespace pdmesh {

// The relative width of the tie band of metric_incircle: |D| <= kMetricIncircleTie * P counts as
// cocircular (D the in-circle determinant in the metric, P the sum of its terms' magnitudes). It is
// ~500 times the rounding error of D, so the two diagonals of one quadrilateral can never both ask
// for a flip (no flip is undone at once), and cocircular points in the metric flip nothing.
inline constexpr double kMetricIncircleTie = 1e-12;

// The in-circle test in the constant metric m: +1 when d lies strictly inside the ellipse through
// a, b, c (counter-clockwise) that is a circle in m, -1 when strictly outside, 0 within the tie band.
// Equal to the sign of incircle(La, Lb, Lc, Ld) for LᵀL = m, outside the tie band.
int metric_incircle(Vec2 a, Vec2 b, Vec2 c, Vec2 d, const Metric& m);

struct MetricDelaunayOptions {
  // The most flips made; 0 = the default bound, kMetricFlipsPerEdge flips per edge of the start
  // triangulation. When reached, the pass stops with a valid triangulation that is not yet metric
  // Delaunay everywhere (MetricDelaunayStats::converged = false).
  std::size_t max_flips = 0;
};
// The default flip bound per edge (see make_metric_delaunay on termination).
inline constexpr std::size_t kMetricFlipsPerEdge = 64;

struct MetricDelaunayStats {
  std::size_t flips = 0;
  std::size_t tests = 0;      // in-circle tests in the metric
  std::size_t max_flips = 0;  // the bound used
  bool converged = true;      // false when the bound stopped the pass
};

// Flips the edges of `tri` until every edge that may flip passes the metric in-circle test, with
// metrics[i] the metric at input point i (tri.input_index). An edge may flip when it is not
// constrained, no vertex of its two triangles is a super-triangle vertex (those are outside the
// input's hull: the hull edges stay as the isotropic triangulation has them), and its quadrilateral
// is strictly convex in physical space by the exact orient2d, so that no triangle is ever inverted
// or flat. The criterion for the edge a-b of triangles (p, a, b) and (q, b, a) is
// metric_incircle(p, a, b, q, M) > 0 with M = exp(¼ Σ log M_v) over {p, a, b, q}: the same M for
// both diagonals of the quadrilateral (summed in vertex order, so bit for bit), hence the test is
// antisymmetric and a flip is never undone by the next test of the same quadrilateral.
// Termination: with one constant metric this is Lawson's algorithm on the mapped points, which
// ends. With a varying metric each quadrilateral has its own M and no global potential decreases,
// so cycles through several quadrilaterals are possible in principle: the pass stops after
// options.max_flips flips (default kMetricFlipsPerEdge per edge) and reports converged = false.
// Throws InputError naming the point when a metric is not SPD, or when metrics.size() differs from
// the number of input points.
MetricDelaunayStats make_metric_delaunay(Triangulation& tri, const std::vector<Metric>& metrics,
                                         const MetricDelaunayOptions& options = {});

// The edges of `tri` (vertex pairs in input point indices) that make_metric_delaunay would flip
// now: empty after a converged pass. For tests and diagnostics.
std::vector<std::array<int, 2>> metric_delaunay_violations(const Triangulation& tri,
                                                           const std::vector<Metric>& metrics);

}  // namespace pdmesh
