// TimeExpression: one muParser expression in t (time_expression.hpp).
#include "motion/time_expression.hpp"

#include <cmath>
#include <fmt/format.h>
#include <muParser.h>

#include "core/errors.hpp"

namespace pdmesh {

// muParser binds t by address: the parser and its variable live together on the heap.
struct TimeExpression::Impl {
  std::string expression;
  std::string what;
  mu::Parser parser;
  double t = 0.0;
};

TimeExpression::TimeExpression(const std::string& expression, std::string what) : impl_(std::make_unique<Impl>()) {
  impl_->expression = expression;
  impl_->what = std::move(what);
  try {
    impl_->parser.DefineVar("t", &impl_->t);
    impl_->parser.DefineConst("pi", M_PI);
    impl_->parser.SetExpr(expression);
    impl_->parser.Eval();  // parses now, so that syntax errors are reported at set-up
  } catch (const mu::Parser::exception_type& e) {
    throw InputError(fmt::format("{} '{}': {}", impl_->what, expression, e.GetMsg()));
  }
}

TimeExpression::~TimeExpression() = default;
TimeExpression::TimeExpression(TimeExpression&&) noexcept = default;
TimeExpression& TimeExpression::operator=(TimeExpression&&) noexcept = default;

double TimeExpression::operator()(double t) const {
  impl_->t = t;
  double v = 0.0;
  try {
    v = impl_->parser.Eval();
  } catch (const mu::Parser::exception_type& e) {
    throw InputError(fmt::format("{} '{}' at t = {}: {}", impl_->what, impl_->expression, t, e.GetMsg()));
  }
  if (!std::isfinite(v))
    throw InputError(
        fmt::format("{} '{}' at t = {} gives {}; it must be a finite number", impl_->what, impl_->expression, t, v));
  return v;
}

}  // namespace pdmesh
