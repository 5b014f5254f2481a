// A scalar function u(x, y) given as a muParser expression (constant pi): the solution a Hessian
// metric adapts to (spacing/hessian_metric.hpp).
#pragma once
#include <memory>
#include <string>

#include "core/vec2.hpp"

namespace pdmesh {

// The constructor throws InputError naming the expression on a syntax error or an unknown name;
// operator() throws InputError naming the expression, the point and the value when the value is not
// finite. Not thread-safe (one muParser instance; give each thread its own).
class ScalarExpression {
 public:
  explicit ScalarExpression(const std::string& expression);
  ~ScalarExpression();
  ScalarExpression(ScalarExpression&&) noexcept;
  double operator()(Vec2 p) const;
  const std::string& expression() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace pdmesh
