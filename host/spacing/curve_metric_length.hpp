// The metric length of a stretch of a curve: the integral of |t|_M ds along the polyline between two
// arc positions, t the unit tangent of each segment and M the field's metric at each point. The
// boundary stations of a metric run are placed at unit steps of this integral (init/metric_fill's
// CurveMetricSpacing through spacing_stations); measured between two boundary nodes it tells how
// many unit steps the curve between them holds, also where the metric varies so much along the
// stretch that the chord's two end metrics miss (a curve node on a layer's inflection line, where a
// Hessian metric's sizes are far larger than beside it). Population control's boundary gaps and the
// cleanup's boundary edges go by it (docs/metric-fields.md, "Population control in the metric" and
// "Cleanup in the metric").
#pragma once
#include "geometry/geometry.hpp"
#include "spacing/metric_field.hpp"

namespace pdmesh {

// Sub-intervals of the midpoint rule per polyline piece between two curve points.
inline constexpr int kCurveMetricSamples = 8;

// The integral of |t|_M ds over `curve` between arc positions arc_a and arc_b (either order; clamped
// to the curve), by the midpoint rule on kCurveMetricSamples equal sub-intervals of each polyline
// piece. 0 when arc_a == arc_b.
double curve_metric_length(const Curve& curve, const MetricField& metric, double arc_a, double arc_b);

// The arc position between arc_a and arc_b (either order) that halves curve_metric_length over that
// stretch, by bisection to a relative 1e-9 of the stretch; (arc_a + arc_b) / 2 when the length is 0.
double curve_metric_half(const Curve& curve, const MetricField& metric, double arc_a, double arc_b);

}  // namespace pdmesh
