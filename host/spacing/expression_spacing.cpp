// ExpressionSpacing: q(x, y) from a user expression evaluated by muParser (e.g. thesis eq. 7.2).
#include <cmath>
#include <fmt/format.h>

#include "core/errors.hpp"
#include "spacing/scalar_expression.hpp"
#include "spacing/spacing_field.hpp"

namespace pdmesh {

// One muParser instance, mutated by the const at(): one ExpressionSpacing must not be used from
// several threads at once (give each thread its own). ScalarExpression parses at set-up, so that
// syntax errors and unknown names are reported then, not in the middle of a simulation.
struct ExpressionSpacing::Impl {
  explicit Impl(const std::string& expression) : q(expression, "spacing expression") {}
  ScalarExpression q;
};

ExpressionSpacing::ExpressionSpacing(const std::string& expression) : impl_(std::make_unique<Impl>(expression)) {}

ExpressionSpacing::~ExpressionSpacing() = default;

double ExpressionSpacing::at(Vec2 p) const {
  const double q = impl_->q.evaluate(p);
  if (!std::isfinite(q) || q <= 0.0)
    throw InputError(
        fmt::format("spacing expression '{}' at ({}, {}) gives {}; the spacing must be a finite "
                    "positive number",
                    impl_->q.expression(), p.x, p.y, q));
  return q;
}

}  // namespace pdmesh
