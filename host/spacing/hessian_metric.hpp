// The L^p-optimal metric of a Hessian (Loseille & Alauzet, "Continuous mesh framework", 2-D): the
// metric whose unit mesh of a given complexity C minimises the L^p norm of the P1 interpolation error
// of u, M = D det|H|^(-1/(2p+2)) |H|, with |H| the Hessian's absolute value (eigenvalues |lambda|)
// and D = C / ∫ det|H|^(p/(2p+2)) so that ∫ sqrt(det M) = C; then clipped to sizes in
// [hmin, hmax] and a largest anisotropy. For p = 2: M = D det|H|^(-1/6) |H|. The same formulas as
// tools/eval/pdmesh_eval/metric.py's l2_optimal_metric.
#pragma once
#include <array>
#include <limits>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "core/vec2.hpp"
#include "core/lease_pool.hpp"
#include "spacing/hessian.hpp"
#include "spacing/metric.hpp"
#include "spacing/metric_field.hpp"
#include "spacing/scalar_expression.hpp"

namespace pdmesh {

struct HessianMetricOptions {
  double complexity = 1000.0;  // C = ∫ sqrt(det M), before clipping (about 1.15 C vertices)
  double p = 2.0;              // the error's norm, L^p (1 <= p; p = 2 the L2 norm)
  double hmin = 0.0;           // smallest size (0: none)
  double hmax = std::numeric_limits<double>::infinity();            // largest size
  double max_anisotropy = std::numeric_limits<double>::infinity();  // largest h_max / h_min of one metric
  double floor = 1e-8;  // |H|'s eigenvalues are floored here (where u is flat, H = 0)
};

// Throws InputError naming the option and its value: complexity not finite and > 0, p < 1 or not
// finite, hmin < 0, hmax <= hmin, max_anisotropy < 1, floor not finite and > 0.
void check_hessian_metric_options(const HessianMetricOptions& o);

// |H| = R diag(max(|lambda_i|, floor)) Rᵀ: an SPD matrix.
Metric abs_hessian(const Hessian& h, double floor);
// det|H|^(p/(2p+2)) with |H| = abs_hessian(h, floor): the integrand of D's denominator.
double hessian_density(const Hessian& h, const HessianMetricOptions& o);
// D det|H|^(-1/(2p+2)) |H|, then clipped (clip_metric).
Metric lp_optimal_metric(const Hessian& h, double scale, const HessianMetricOptions& o);
// The eigenvalues clipped to [1/hmax², 1/hmin²], then the smaller raised to at least
// lambda1 / max_anisotropy² (the largest size at most max_anisotropy times the smallest).
Metric clip_metric(const Metric& m, double hmin, double hmax, double max_anisotropy);

// The L^p-optimal metrics at the points of a triangle mesh from data u at its points: Hessians by
// recover_hessians, D from ∫ density by the P1 rule on the triangles (the mean of the corners times
// the area), then lp_optimal_metric. Throws InputError as recover_hessians and
// check_hessian_metric_options do, naming `what`.
std::vector<Metric> hessian_metrics_on_mesh(const std::vector<Vec2>& points,
                                            const std::vector<std::array<int, 3>>& triangles,
                                            const std::vector<double>& u, const HessianMetricOptions& o,
                                            std::string_view what);

// Several arrays at the points of one mesh (multi-variable adaptation, Loseille & Alauzet): each array
// divided by its range max - min (1 where it is constant), so that each is resolved to the same error
// relative to its own variation whatever its units; each one's L^p metric before its scale,
// det|H_k|^(-1/(2p+2)) |H_k| (lp_unscaled_metric); their intersection at each point; then one scale
// D = C / ∫ sqrt(det M) (complexity_scale) over the intersection, and clip_metric. The intersection
// comes before the scale because each array's own D would spread C over its feature alone; the one
// D puts the intersected metric at complexity C. One array is hessian_metrics_on_mesh, whose D makes
// the division by the range cancel. `what` names each array in messages (as many as `arrays`).
std::vector<Metric> intersected_hessian_metrics_on_mesh(const std::vector<Vec2>& points,
                                                        const std::vector<std::array<int, 3>>& triangles,
                                                        const std::vector<std::vector<double>>& arrays,
                                                        const HessianMetricOptions& o,
                                                        const std::vector<std::string>& what);
// det|H|^(-1/(2p+2)) |H| with |H| = abs_hessian(h, o.floor): lp_optimal_metric before its scale and clip.
Metric lp_unscaled_metric(const Hessian& h, const HessianMetricOptions& o);
// C / ∫ sqrt(det m) by the P1 rule on the triangles (the mean of the corners times the area): the
// factor that gives the metrics m complexity C. Throws InputError naming `what` when the integral is 0.
double complexity_scale(const std::vector<Vec2>& points, const std::vector<std::array<int, 3>>& triangles,
                        const std::vector<Metric>& m, double complexity, std::string_view what);
// An array divided by its range max - min (by 1 where the range is 0).
std::vector<double> divided_by_range(const std::vector<double>& u);

// The metric field of a function u given as an expression: the Hessian by central differences of
// step `step` (hessian_by_differences), D from the midpoint rule of the density on a grid x grid
// grid over `box` (as metric.py's l2_optimal_scale). at() is not thread-safe (one muParser instance);
// at_many() gives at()'s values on several threads, each with its own parser.
class HessianMetricField final : public MetricField {
 public:
  HessianMetricField(const std::string& expression, const Box& box, const HessianMetricOptions& o, double step,
                     int grid = 1024);
  Metric at(Vec2 p) const override;
  void at_many(const std::vector<Vec2>& p, std::vector<Metric>& out, std::vector<int>& guesses) const override;
  Hessian hessian(Vec2 p) const;
  double scale() const { return scale_; }

 private:
  ScalarExpression u_;
  mutable LeasePool<ScalarExpression> parsers_;  // at_many's, one per thread
  HessianMetricOptions options_;
  double step_;
  double scale_ = 1.0;
};

// The metrics of `field` at the vertices of an n x n grid over `box`, widened by half a cell on every
// side so that the box's edges lie inside: (n+1)² points, row by row from box.lo, and 2n² counter-
// clockwise triangles. A function's metric as data on a background mesh, for metric gradation along
// the grid's edges (spacing.metric_gradation with spacing.function). n >= 1.
void sample_metric_grid(const MetricField& field, const Box& box, int n, std::vector<Vec2>& points,
                        std::vector<std::array<int, 3>>& triangles, std::vector<Metric>& metrics);

}  // namespace pdmesh
