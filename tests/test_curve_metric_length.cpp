// The metric length of a stretch of a curve (host/spacing/curve_metric_length): in a constant metric it
// is |t|_M times the arc length on each straight piece, in either order of the ends, clamped to the
// curve; where the metric shrinks along the curve between two points it is what the chord's two end
// metrics miss; curve_metric_half halves it.
#include <catch2/catch.hpp>

#include <cmath>
#include <vector>

#include "geometry/geometry.hpp"
#include "spacing/curve_metric_length.hpp"
#include "spacing/metric.hpp"
#include "spacing/metric_field.hpp"

using namespace pdmesh;

namespace {

// Size 1 everywhere but near `centre`, where the metric grows by (1 + depth e^(-|p - c|²/w²))²: a
// narrow place of small sizes.
class NarrowSmall final : public MetricField {
 public:
  NarrowSmall(Vec2 centre, double depth, double width) : c_(centre), depth_(depth), w_(width) {}
  Metric at(Vec2 p) const override {
    const double s = 1.0 + depth_ * std::exp(-norm2(p - c_) / (w_ * w_));
    return {s * s, 0.0, s * s};
  }

 private:
  Vec2 c_;
  double depth_, w_;
};

// An open polyline as a Curve (points and cumulative arc length).
Curve polyline(const std::vector<Vec2>& points) {
  Curve c;
  c.name = "test";
  c.points = points;
  c.arc.push_back(0.0);
  for (std::size_t k = 1; k < points.size(); ++k) c.arc.push_back(c.arc.back() + dist(points[k - 1], points[k]));
  c.critical.assign(points.size(), 0);
  return c;
}

}  // namespace

TEST_CASE("curve metric length: a constant metric gives |t|_M times the arc length", "[metric]") {
  // An L: 2 along x, then 1 along y; sizes 0.5 along x and 0.25 along y.
  const Curve curve = polyline({{0, 0}, {2, 0}, {2, 1}});
  const ConstantMetricField field(metric_from_sizes(0.5, 0.25, 0.0));
  CHECK(curve_metric_length(curve, field, 0.0, 3.0) == Approx(2.0 / 0.5 + 1.0 / 0.25).epsilon(1e-12));
  CHECK(curve_metric_length(curve, field, 3.0, 0.0) == Approx(8.0).epsilon(1e-12));  // either order
  CHECK(curve_metric_length(curve, field, 1.5, 2.5) == Approx(0.5 / 0.5 + 0.5 / 0.25).epsilon(1e-12));
  CHECK(curve_metric_length(curve, field, -1.0, 9.0) == Approx(8.0).epsilon(1e-12));  // clamped
  CHECK(curve_metric_length(curve, field, 1.0, 1.0) == 0.0);
  // Half of 1.5..2.5 (1 + 2 metric units) lies on the y leg, 0.25 past the corner at arc 2.
  CHECK(curve_metric_half(curve, field, 1.5, 2.5) == Approx(2.125).epsilon(1e-9));
}

TEST_CASE("curve metric length sees small sizes between two points that the chord's ends miss", "[metric]") {
  // A straight curve from (0, 0) to (1, 0) in 4 segments; sizes 1/21 at (0.5, 0), width 0.05.
  const Curve curve = polyline({{0, 0}, {0.25, 0}, {0.5, 0}, {0.75, 0}, {1, 0}});
  const NarrowSmall field({0.5, 0.0}, 20.0, 0.05);
  // The chord from 0.25 to 0.75 measured by its end metrics (the small sizes 5 widths away): its length.
  const double chord = edge_length(field.at({0.25, 0}), field.at({0.75, 0}), {0.5, 0});
  CHECK(chord == Approx(0.5).epsilon(1e-9));
  // Along the curve: 0.5 + 20 * 0.05 * sqrt(pi) (the Gaussian's integral; its tails beyond 5 widths
  // are below 1e-10).
  const double along = curve_metric_length(curve, field, 0.25, 0.75);
  CHECK(along == Approx(0.5 + 20.0 * 0.05 * std::sqrt(M_PI)).epsilon(1e-6));
  CHECK(curve_metric_half(curve, field, 0.25, 0.75) == Approx(0.5).margin(1e-6));
}
