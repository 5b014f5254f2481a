// The metric at the geometry's fixed points graded from the field around them (fixed_point_metric.hpp).
#include "spacing/fixed_point_metric.hpp"

#include <algorithm>
#include <cmath>

namespace pdmesh {

namespace {

// Rays from the point and rings along them: 16 directions half a step off the axes (so that no ray runs
// along an axis-parallel curve through the point), distances from the point's largest size down by
// factors of sqrt(2) to about 1e-7 of it, where no mesh node will stand.
constexpr int kRays = 16;
constexpr int kRings = 48;
// A span is taken where it asks for sizes at least 1 % smaller (squared: 1.02) in some direction.
constexpr double kTaken = 1.02;

bool before(Vec2 a, Vec2 b) { return a.x < b.x || (a.x == b.x && a.y < b.y); }

}  // namespace

Metric graded_from_around(const MetricField& field, const GeometryTree& tree, Vec2 p, double beta) {
  const Metric own = field.at(p);
  const MetricEigen e = eigen(own);
  const double largest = 1.0 / std::sqrt(e.lambda2);
  // The point at ring k along ray d, where it lies in the domain and is seen from p.
  const auto point = [&](int k, int d, Vec2& q) {
    const double r = largest * std::pow(0.5, 0.5 * k);
    const double a = (d + 0.5) * (2.0 * M_PI / kRays);
    q = Vec2{p.x + r * std::cos(a), p.y + r * std::sin(a)};
    return !(q.x == p.x && q.y == p.y) && tree.inside(q) && !tree.crosses_boundary(p, q);
  };
  // The field just beside p (the innermost ring, where a span grows by a few 1e-8): where its mean asks
  // for sizes no smaller than 1/beta of p's in any direction, the field is continuous at p (up to the
  // rounding noise of a Hessian by differences where u is nearly flat) and p keeps its own metric.
  std::vector<Metric> beside;
  for (int d = 0; d < kRays; ++d) {
    Vec2 q;
    if (point(kRings - 1, d, q)) beside.push_back(field.at(q));
  }
  const bool singular =
      !beside.empty() &&
      largest_metric_ratio(own, log_euclidean_mean(beside, std::vector<double>(beside.size(), 1.0))) > beta * beta;
  if (!singular) return own;
  Metric m = own;
  for (int k = 0; k < kRings; ++k)
    for (int d = 0; d < kRays; ++d) {
      Vec2 q;
      if (!point(k, d, q)) continue;
      const Metric span = span_metric(field.at(q), p - q, beta, 0.0);
      if (largest_metric_ratio(m, span) > kTaken) m = intersect(m, span);
    }
  return m;
}

PointMetricField::PointMetricField(std::unique_ptr<MetricField> field, std::vector<std::pair<Vec2, Metric>> points)
    : field_(std::move(field)), points_(std::move(points)) {
  std::sort(points_.begin(), points_.end(), [](const auto& a, const auto& b) { return before(a.first, b.first); });
}

const Metric* PointMetricField::given(Vec2 p) const {
  const auto it = std::lower_bound(points_.begin(), points_.end(), p,
                                   [](const auto& entry, Vec2 v) { return before(entry.first, v); });
  return it != points_.end() && it->first.x == p.x && it->first.y == p.y ? &it->second : nullptr;
}

Metric PointMetricField::at(Vec2 p) const {
  const Metric* m = given(p);
  return m != nullptr ? *m : field_->at(p);
}

void PointMetricField::at_many(const std::vector<Vec2>& p, std::vector<Metric>& out, std::vector<int>& guesses) const {
  field_->at_many(p, out, guesses);
  for (std::size_t i = 0; i < p.size(); ++i)
    if (const Metric* m = given(p[i])) out[i] = *m;
}

std::unique_ptr<MetricField> with_fixed_point_metrics(std::unique_ptr<MetricField> field, const GeometryTree& tree,
                                                      double beta) {
  const Geometry& g = tree.geometry();
  std::vector<Vec2> fixed;
  for (const CriticalPoint& c : g.critical) {
    const bool placed_by_curve =
        std::all_of(c.curves.begin(), c.curves.end(), [&](int curve) { return g.curves[curve].fixed_points; });
    if (!c.curves.empty() && placed_by_curve) continue;
    fixed.push_back(c.p);
  }
  for (const RawPoint& e : g.embedded_points) fixed.push_back(e.p);
  std::vector<std::pair<Vec2, Metric>> changed;
  for (const Vec2 p : fixed) {
    const Metric own = field->at(p);
    const Metric graded = graded_from_around(*field, tree, p, beta);
    if (graded.m11 != own.m11 || graded.m12 != own.m12 || graded.m22 != own.m22) changed.emplace_back(p, graded);
  }
  if (changed.empty()) return field;
  return std::make_unique<PointMetricField>(std::move(field), std::move(changed));
}

}  // namespace pdmesh
