// ExpressionSpacing: q(x, y) from a user expression evaluated by muParser (e.g. thesis eq. 7.2).
#include <muParser.h>

#include <cmath>
#include <fmt/format.h>

#include "core/errors.hpp"
#include "spacing/spacing_field.hpp"

namespace pdmesh {

// muParser binds variables by address and evaluates through internal state, so the parser and its
// variables live together here and are mutated by the const at(): one ExpressionSpacing must not be
// used from several threads at once (give each thread its own).
struct ExpressionSpacing::Impl {
  std::string expression;
  mu::Parser parser;
  double x = 0.0;
  double y = 0.0;
};

ExpressionSpacing::ExpressionSpacing(const std::string& expression) : impl_(std::make_unique<Impl>()) {
  impl_->expression = expression;
  try {
    impl_->parser.DefineVar("x", &impl_->x);
    impl_->parser.DefineVar("y", &impl_->y);
    impl_->parser.DefineConst("pi", M_PI);
    impl_->parser.SetExpr(expression);
    // muParser parses lazily; one evaluation here reports syntax errors and unknown names now,
    // at set-up, instead of in the middle of a simulation. Its value is not checked here.
    impl_->parser.Eval();
  } catch (const mu::Parser::exception_type& e) {
    throw InputError(fmt::format("spacing expression '{}': {}", expression, e.GetMsg()));
  }
}

ExpressionSpacing::~ExpressionSpacing() = default;

double ExpressionSpacing::at(Vec2 p) const {
  impl_->x = p.x;
  impl_->y = p.y;
  double q;
  try {
    q = impl_->parser.Eval();
  } catch (const mu::Parser::exception_type& e) {
    throw InputError(fmt::format("spacing expression '{}' at ({}, {}): {}", impl_->expression, p.x, p.y, e.GetMsg()));
  }
  if (!std::isfinite(q) || q <= 0.0)
    throw InputError(
        fmt::format("spacing expression '{}' at ({}, {}) gives {}; the spacing must be a finite "
                    "positive number",
                    impl_->expression, p.x, p.y, q));
  return q;
}

}  // namespace pdmesh
