// A scalar function u(x, y) given as a muParser expression (constant pi): the solution a Hessian
// metric adapts to (spacing/hessian_metric.hpp).
#pragma once
#include <memory>
#include <string>

#include "core/vec2.hpp"

namespace pdmesh {

// The constructor throws InputError naming the expression on a syntax error or an unknown name
// (messages begin with `what`, e.g. "spacing expression"); evaluate() throws InputError naming the
// expression and the point when muParser fails there, and operator() also when the value is not
// finite. Not thread-safe (one muParser instance; give each thread its own).
class ScalarExpression {
 public:
  explicit ScalarExpression(const std::string& expression, std::string what = "expression");
  ~ScalarExpression();
  ScalarExpression(ScalarExpression&&) noexcept;
  double operator()(Vec2 p) const;
  double evaluate(Vec2 p) const;  // the value as muParser gives it, not checked
  const std::string& expression() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace pdmesh
