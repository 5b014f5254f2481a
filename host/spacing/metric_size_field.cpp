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

void MetricSizeField::at_many(const std::vector<Vec2>& p, std::vector<double>& q) const {
  std::vector<Metric> m;
  std::vector<int> guesses;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    metric_.at_many(p, m, guesses);
  }
  q.resize(p.size());
  for (std::size_t i = 0; i < p.size(); ++i) q[i] = isotropic_size(m[i]);
}

}  // namespace pdmesh
