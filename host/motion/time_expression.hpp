// A function of time t given as a muParser expression (constants _pi, _e and pi): the angle and the
// translation of a [motion] section (docs/motion.md).
#pragma once
#include <memory>
#include <string>

namespace pdmesh {

// The constructor throws InputError naming `what` and the expression on a syntax error or an unknown
// name; operator() throws InputError naming t when the value is not a finite number. Not thread-safe.
class TimeExpression {
 public:
  TimeExpression(const std::string& expression, std::string what);
  ~TimeExpression();
  TimeExpression(TimeExpression&&) noexcept;
  TimeExpression& operator=(TimeExpression&&) noexcept;
  double operator()(double t) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace pdmesh
