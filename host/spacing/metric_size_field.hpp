// The isotropic spacing a metric run's pipeline uses until the particles take the metric itself:
// q(x) = det M(x)^(-1/4) = sqrt(h1 h2), the size whose disc has the area of the metric's unit ellipse
// (pi h1 h2). A unit mesh of M and an isotropic mesh of this q then have the same element count,
// about 4C/sqrt(3) triangles with C = ∫ sqrt(det M), so boundary placement, the node estimate, the
// initialization and the simulation work unchanged and place as many nodes as the metric asks for
// (isotropically: docs/metric-fields.md, "In a case file").
#pragma once
#include <memory>
#include <mutex>
#include <vector>

#include "spacing/metric_field.hpp"
#include "spacing/spacing_field.hpp"

namespace pdmesh {

// det m^(-1/4), from the eigenvalues (accurate for very anisotropic metrics).
double isotropic_size(const Metric& m);

// at() and at_many() are thread-safe: the metric field (an expression field is not) is evaluated under
// a lock; at_many() through the field's at_many (its threads). Keeps a reference to `metric`, which
// must outlive it.
class MetricSizeField final : public SpacingField {
 public:
  explicit MetricSizeField(const MetricField& metric) : metric_(metric) {}
  double at(Vec2 p) const override;
  void at_many(const std::vector<Vec2>& p, std::vector<double>& q) const override;

 private:
  const MetricField& metric_;
  mutable std::mutex mutex_;
};

}  // namespace pdmesh
