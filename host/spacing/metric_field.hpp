// Metric fields M(x): the anisotropic counterpart of SpacingField (spacing_field.hpp). A metric field
// gives at every point the SPD matrix that measures edges there (spacing/metric.hpp); the unit mesh
// of M has edges of metric length 1. Read from case files by app/config/case_spacing (make_case_metric).
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "core/vec2.hpp"
#include "spacing/metric.hpp"

namespace pdmesh {

class MetricField {
 public:
  virtual ~MetricField() = default;
  // The metric at p; throws InputError naming the field's source and the value where it is not SPD.
  virtual Metric at(Vec2 p) const = 0;
  // at() at every point of p, into out (resized). `guesses` is the caller's per-point memory for the
  // field (resized to p.size(); kept between calls for the same moving points, it saves searches).
  // This one calls at() in order; a field may do better with the same values.
  virtual void at_many(const std::vector<Vec2>& p, std::vector<Metric>& out, std::vector<int>& guesses) const;
};

// The same metric everywhere (checked on construction).
class ConstantMetricField final : public MetricField {
 public:
  explicit ConstantMetricField(const Metric& m);
  Metric at(Vec2) const override { return m_; }

 private:
  Metric m_;
};

// Three muParser expressions in x and y (constant pi), in one of two forms:
//   sizes:       h1, h2 and angle, the direction of h1 in degrees from the x axis:
//                M = R(angle) diag(1/h1², 1/h2²) R(angle)ᵀ;
//   components:  m11, m12 and m22 of M directly.
// The constructor throws InputError naming the expression on a syntax error or an unknown name;
// at() throws InputError naming the expression, the point and the value when a size is not a finite
// positive number, the angle is not finite, or the components are not a finite SPD matrix.
// at() is not thread-safe (it drives one set of muParser instances); at_many() gives at()'s values on
// several threads, each with parsers of its own.
class ExpressionMetricField final : public MetricField {
 public:
  enum class Form { sizes, components };
  ExpressionMetricField(Form form, const std::string& e1, const std::string& e2, const std::string& e3);
  ~ExpressionMetricField() override;
  Metric at(Vec2 p) const override;
  void at_many(const std::vector<Vec2>& p, std::vector<Metric>& out, std::vector<int>& guesses) const override;

  static ExpressionMetricField from_sizes(const std::string& h1, const std::string& h2, const std::string& angle_deg) {
    return ExpressionMetricField(Form::sizes, h1, h2, angle_deg);
  }
  static ExpressionMetricField from_components(const std::string& m11, const std::string& m12, const std::string& m22) {
    return ExpressionMetricField(Form::components, m11, m12, m22);
  }
  ExpressionMetricField(ExpressionMetricField&&) noexcept;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace pdmesh
