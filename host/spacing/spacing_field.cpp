// The SpacingField base: the default many-point evaluation.
#include "spacing/spacing_field.hpp"

namespace pdmesh {

void SpacingField::at_many(const std::vector<Vec2>& p, std::vector<double>& q) const {
  q.resize(p.size());
  for (std::size_t i = 0; i < p.size(); ++i) q[i] = at(p[i]);
}

void SpacingField::at_many_guessed(const std::vector<Vec2>& p, std::vector<double>& q,
                                   std::vector<int>& guesses) const {
  guesses.resize(p.size());
  at_many(p, q);
}

}  // namespace pdmesh
