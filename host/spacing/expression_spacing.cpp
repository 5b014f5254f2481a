// ExpressionSpacing: q(x, y) from a user expression evaluated by muParser (e.g. thesis eq. 7.2).
#include <cmath>
#include <fmt/format.h>

#include "core/errors.hpp"
#include "core/lease_pool.hpp"
#include "core/parallel.hpp"
#include "spacing/scalar_expression.hpp"
#include "spacing/spacing_field.hpp"

namespace pdmesh {

// ScalarExpression parses at set-up, so that syntax errors and unknown names are reported then, not in
// the middle of a simulation. One parser is at()'s; at_many's threads each lease one of their own.
struct ExpressionSpacing::Impl {
  explicit Impl(const std::string& expression)
      : q(expression, kWhat), pool([expression] { return std::make_unique<ScalarExpression>(expression, kWhat); }) {}
  static constexpr const char* kWhat = "spacing expression";
  ScalarExpression q;
  LeasePool<ScalarExpression> pool;
};

namespace {

double checked_spacing(const ScalarExpression& e, Vec2 p) {
  const double q = e.evaluate(p);
  if (!std::isfinite(q) || q <= 0.0)
    throw InputError(
        fmt::format("spacing expression '{}' at ({}, {}) gives {}; the spacing must be a finite "
                    "positive number",
                    e.expression(), p.x, p.y, q));
  return q;
}

}  // namespace

ExpressionSpacing::ExpressionSpacing(const std::string& expression) : impl_(std::make_unique<Impl>(expression)) {}

ExpressionSpacing::~ExpressionSpacing() = default;

double ExpressionSpacing::at(Vec2 p) const { return checked_spacing(impl_->q, p); }

void ExpressionSpacing::at_many(const std::vector<Vec2>& p, std::vector<double>& q) const {
  q.resize(p.size());
  parallel_for_scratch<LeasePool<ScalarExpression>::Lease>(
      p.size(),
      [&](LeasePool<ScalarExpression>::Lease& e, std::size_t i) {
        if (!e) e = impl_->pool.take();
        q[i] = checked_spacing(*e, p[i]);
      },
      kExpressionPointsPerThread);
}

}  // namespace pdmesh
