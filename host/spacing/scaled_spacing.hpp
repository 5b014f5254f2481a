// ScaledSpacing: a spacing field times a constant, evaluated through the base's own at_many so that
// batches stay batches (the pipeline's base x spacing.scale, and the field as asked when the nodes
// relax at spacing.relax_scale times it).
#pragma once
#include <vector>

#include "spacing/spacing_field.hpp"

namespace pdmesh {

class ScaledSpacing final : public SpacingField {
 public:
  // `base` must outlive this field.
  ScaledSpacing(const SpacingField& base, double scale) : base_(base), scale_(scale) {}
  double at(Vec2 p) const override { return scale_ * base_.at(p); }
  void at_many(const std::vector<Vec2>& p, std::vector<double>& q) const override {
    base_.at_many(p, q);
    for (double& v : q) v *= scale_;
  }

 private:
  const SpacingField& base_;
  double scale_;
};

}  // namespace pdmesh
