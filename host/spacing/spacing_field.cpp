// The SpacingField base: the default many-point evaluation.
#include "spacing/spacing_field.hpp"

namespace pdmesh {

void SpacingField::at_many(const std::vector<Vec2>& p, std::vector<double>& q) const {
  q.resize(p.size());
  for (std::size_t i = 0; i < p.size(); ++i) q[i] = at(p[i]);
}

void SpacingField::at_many_closest(const std::vector<Vec2>& p, std::vector<double>& q, std::vector<int>& closest,
                                   const Geometry&) const {
  at_many(p, q);
  closest.assign(p.size(), -1);
}

}  // namespace pdmesh
