// ScalarExpression: one muParser expression in x and y (scalar_expression.hpp).
#include "spacing/scalar_expression.hpp"

#include <fmt/format.h>
#include <muParser.h>

#include <cmath>

#include "core/errors.hpp"

namespace pdmesh {

// muParser binds x and y by address: the parser and its variables live together on the heap.
struct ScalarExpression::Impl {
  std::string expression;
  std::string what;
  mu::Parser parser;
  double x = 0.0;
  double y = 0.0;
};

ScalarExpression::ScalarExpression(const std::string& expression, std::string what) : impl_(std::make_unique<Impl>()) {
  impl_->expression = expression;
  impl_->what = std::move(what);
  try {
    impl_->parser.DefineVar("x", &impl_->x);
    impl_->parser.DefineVar("y", &impl_->y);
    impl_->parser.DefineConst("pi", M_PI);
    impl_->parser.SetExpr(expression);
    impl_->parser.Eval();  // parses now, so that syntax errors are reported at set-up
  } catch (const mu::Parser::exception_type& e) {
    throw InputError(fmt::format("{} '{}': {}", impl_->what, expression, e.GetMsg()));
  }
}

ScalarExpression::~ScalarExpression() = default;
ScalarExpression::ScalarExpression(ScalarExpression&&) noexcept = default;

const std::string& ScalarExpression::expression() const { return impl_->expression; }

double ScalarExpression::evaluate(Vec2 p) const {
  impl_->x = p.x;
  impl_->y = p.y;
  try {
    return impl_->parser.Eval();
  } catch (const mu::Parser::exception_type& e) {
    throw InputError(fmt::format("{} '{}' at ({}, {}): {}", impl_->what, impl_->expression, p.x, p.y, e.GetMsg()));
  }
}

double ScalarExpression::operator()(Vec2 p) const {
  const double u = evaluate(p);
  if (!std::isfinite(u))
    throw InputError(fmt::format("{} '{}' at ({}, {}) gives {}; it must be a finite number", impl_->what,
                                 impl_->expression, p.x, p.y, u));
  return u;
}

}  // namespace pdmesh
