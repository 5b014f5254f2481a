// Metric fields: a constant metric and three muParser expressions (metric_field.hpp).
#include "spacing/metric_field.hpp"

#include <fmt/format.h>
#include <muParser.h>

#include <array>
#include <cmath>
#include <memory>

#include "core/errors.hpp"
#include "core/lease_pool.hpp"
#include "core/parallel.hpp"
#include "spacing/spacing_field.hpp"

namespace pdmesh {

void MetricField::at_many(const std::vector<Vec2>& p, std::vector<Metric>& out, std::vector<int>& guesses) const {
  out.resize(p.size());
  guesses.resize(p.size());
  for (std::size_t i = 0; i < p.size(); ++i) out[i] = at(p[i]);
}

ConstantMetricField::ConstantMetricField(const Metric& m) : m_(m) { check_metric(m, "constant metric field"); }

// muParser binds x and y by address and evaluates through internal state: a Parsers holds the three
// parsers and their variables together, and one thread at a time uses it.
namespace {

struct Parsers {
  std::array<mu::Parser, 3> parsers;
  double x = 0.0;
  double y = 0.0;
};

}  // namespace

struct ExpressionMetricField::Impl {
  Form form = Form::sizes;
  std::array<std::string, 3> names;
  std::array<std::string, 3> expressions;
  std::unique_ptr<Parsers> own;                                // at()'s
  LeasePool<Parsers> pool{[this] { return make_parsers(); }};  // at_many()'s, one per thread

  std::string label(int k) const { return fmt::format("metric expression {} = '{}'", names[k], expressions[k]); }
  std::unique_ptr<Parsers> make_parsers() const;
  Metric evaluate(Parsers& parsers, Vec2 p) const;
};

std::unique_ptr<Parsers> ExpressionMetricField::Impl::make_parsers() const {
  auto made = std::make_unique<Parsers>();
  for (int k = 0; k < 3; ++k) {
    try {
      mu::Parser& p = made->parsers[k];
      p.DefineVar("x", &made->x);
      p.DefineVar("y", &made->y);
      p.DefineConst("pi", M_PI);
      p.SetExpr(expressions[k]);
      // muParser parses lazily: one evaluation reports syntax errors and unknown names now.
      p.Eval();
    } catch (const mu::Parser::exception_type& e) {
      throw InputError(fmt::format("{}: {}", label(k), e.GetMsg()));
    }
  }
  return made;
}

Metric ExpressionMetricField::Impl::evaluate(Parsers& parsers, Vec2 p) const {
  parsers.x = p.x;
  parsers.y = p.y;
  std::array<double, 3> v{};
  for (int k = 0; k < 3; ++k) {
    try {
      v[k] = parsers.parsers[k].Eval();
    } catch (const mu::Parser::exception_type& e) {
      throw InputError(fmt::format("{} at ({}, {}): {}", label(k), p.x, p.y, e.GetMsg()));
    }
  }
  if (form == Form::sizes) {
    for (int k = 0; k < 2; ++k)
      if (!std::isfinite(v[k]) || v[k] <= 0.0)
        throw InputError(
            fmt::format("{} at ({}, {}) gives {}; a size must be a finite positive number", label(k), p.x, p.y, v[k]));
    if (!std::isfinite(v[2]))
      throw InputError(
          fmt::format("{} at ({}, {}) gives {}; the angle must be a finite number", label(2), p.x, p.y, v[2]));
    return metric_from_sizes(v[0], v[1], v[2] * (M_PI / 180.0));
  }
  const Metric m{v[0], v[1], v[2]};
  if (!is_spd(m))
    check_metric(m, fmt::format("metric expressions m11 = '{}', m12 = '{}', m22 = '{}' at ({}, {})", expressions[0],
                                expressions[1], expressions[2], p.x, p.y));
  return m;
}

ExpressionMetricField::ExpressionMetricField(Form form, const std::string& e1, const std::string& e2,
                                             const std::string& e3)
    : impl_(std::make_unique<Impl>()) {
  impl_->form = form;
  impl_->expressions = {e1, e2, e3};
  impl_->names = form == Form::sizes ? std::array<std::string, 3>{"h1", "h2", "angle"}
                                     : std::array<std::string, 3>{"m11", "m12", "m22"};
  impl_->own = impl_->make_parsers();
}

ExpressionMetricField::~ExpressionMetricField() = default;
ExpressionMetricField::ExpressionMetricField(ExpressionMetricField&&) noexcept = default;

Metric ExpressionMetricField::at(Vec2 p) const { return impl_->evaluate(*impl_->own, p); }

void ExpressionMetricField::at_many(const std::vector<Vec2>& p, std::vector<Metric>& out,
                                    std::vector<int>& guesses) const {
  out.resize(p.size());
  guesses.resize(p.size());
  Impl& impl = *impl_;
  parallel_for_scratch<LeasePool<Parsers>::Lease>(
      p.size(),
      [&](LeasePool<Parsers>::Lease& parsers, std::size_t i) {
        if (!parsers) parsers = impl.pool.take();
        out[i] = impl.evaluate(*parsers, p[i]);
      },
      kExpressionPointsPerThread);
}

}  // namespace pdmesh
