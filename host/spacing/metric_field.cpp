// Metric fields: a constant metric and three muParser expressions (metric_field.hpp).
#include "spacing/metric_field.hpp"

#include <fmt/format.h>
#include <muParser.h>

#include <array>
#include <cmath>

#include "core/errors.hpp"

namespace pdmesh {

void MetricField::at_many(const std::vector<Vec2>& p, std::vector<Metric>& out, std::vector<int>& guesses) const {
  out.resize(p.size());
  guesses.resize(p.size());
  for (std::size_t i = 0; i < p.size(); ++i) out[i] = at(p[i]);
}

ConstantMetricField::ConstantMetricField(const Metric& m) : m_(m) { check_metric(m, "constant metric field"); }

// As ExpressionSpacing: muParser binds x and y by address and evaluates through internal state, so
// the parsers and their variables live together and are mutated by the const at().
struct ExpressionMetricField::Impl {
  Form form = Form::sizes;
  std::array<std::string, 3> names;
  std::array<std::string, 3> expressions;
  std::array<mu::Parser, 3> parsers;
  double x = 0.0;
  double y = 0.0;

  std::string label(int k) const { return fmt::format("metric expression {} = '{}'", names[k], expressions[k]); }
};

ExpressionMetricField::ExpressionMetricField(Form form, const std::string& e1, const std::string& e2,
                                             const std::string& e3)
    : impl_(std::make_unique<Impl>()) {
  impl_->form = form;
  impl_->expressions = {e1, e2, e3};
  impl_->names = form == Form::sizes ? std::array<std::string, 3>{"h1", "h2", "angle"}
                                     : std::array<std::string, 3>{"m11", "m12", "m22"};
  for (int k = 0; k < 3; ++k) {
    try {
      mu::Parser& p = impl_->parsers[k];
      p.DefineVar("x", &impl_->x);
      p.DefineVar("y", &impl_->y);
      p.DefineConst("pi", M_PI);
      p.SetExpr(impl_->expressions[k]);
      // muParser parses lazily: one evaluation reports syntax errors and unknown names now.
      p.Eval();
    } catch (const mu::Parser::exception_type& e) {
      throw InputError(fmt::format("{}: {}", impl_->label(k), e.GetMsg()));
    }
  }
}

ExpressionMetricField::~ExpressionMetricField() = default;
ExpressionMetricField::ExpressionMetricField(ExpressionMetricField&&) noexcept = default;

Metric ExpressionMetricField::at(Vec2 p) const {
  impl_->x = p.x;
  impl_->y = p.y;
  std::array<double, 3> v{};
  for (int k = 0; k < 3; ++k) {
    try {
      v[k] = impl_->parsers[k].Eval();
    } catch (const mu::Parser::exception_type& e) {
      throw InputError(fmt::format("{} at ({}, {}): {}", impl_->label(k), p.x, p.y, e.GetMsg()));
    }
  }
  if (impl_->form == Form::sizes) {
    for (int k = 0; k < 2; ++k)
      if (!std::isfinite(v[k]) || v[k] <= 0.0)
        throw InputError(fmt::format("{} at ({}, {}) gives {}; a size must be a finite positive number",
                                     impl_->label(k), p.x, p.y, v[k]));
    if (!std::isfinite(v[2]))
      throw InputError(
          fmt::format("{} at ({}, {}) gives {}; the angle must be a finite number", impl_->label(2), p.x, p.y, v[2]));
    return metric_from_sizes(v[0], v[1], v[2] * (M_PI / 180.0));
  }
  const Metric m{v[0], v[1], v[2]};
  if (!is_spd(m))
    check_metric(m, fmt::format("metric expressions m11 = '{}', m12 = '{}', m22 = '{}' at ({}, {})",
                                impl_->expressions[0], impl_->expressions[1], impl_->expressions[2], p.x, p.y));
  return m;
}

}  // namespace pdmesh
