#include "spacing/metric_size_field.hpp"

#include <cmath>

namespace pdmesh {

double isotropic_size(const Metric& m) {
  const MetricEigen e = eigen(m);
  return 1.0 / std::sqrt(std::sqrt(e.lambda1) * std::sqrt(e.lambda2));
}

double MetricSizeField::at(Vec2 p) const {
  std::lock_guard<std::mutex> lock(mutex_);
  return isotropic_size(metric_.at(p));
}

}  // namespace pdmesh
