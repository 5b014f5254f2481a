// The integral of 1 / q^2 over a cell with bilinear q; see inverse_square_integral.hpp.
#include "spacing/inverse_square_integral.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace pdmesh {

namespace {

double unscaled_inverse_square_integral(double q00, double q10, double q01, double q11) {
  // Over u first: the integral of 1 / (a + b u)^2 is 1 / (q(0, v) q(1, v)), with A(v) = q(0, v) and
  // B(v) = q(1, v) linear in v; then the integral over v of 1 / (A B) is ln(B A / (A B))-like:
  // ln((B1 A0) / (A1 B0)) / (A0 B1 - A1 B0).
  const double a0 = q00, a1 = q01, b0 = q10, b1 = q11;
  const double d = a0 * b1 - a1 * b0;
  const double x = d / (a1 * b0);  // (B1 A0) / (A1 B0) = 1 + x
  if (std::fabs(x) < 1e-3) {
    // ln(1 + x) / d = (1 - x / 2 + x^2 / 3 - x^3 / 4) / (A1 B0), error below x^4 / 5.
    return (1.0 - x * (0.5 - x * (1.0 / 3.0 - 0.25 * x))) / (a1 * b0);
  }
  return std::log1p(x) / d;
}

}  // namespace

double inverse_square_integral(double q00, double q10, double q01, double q11) {
  const double lo = std::min(std::min(q00, q10), std::min(q01, q11));
  const double hi = std::max(std::max(q00, q10), std::max(q01, q11));
  // The products of two q overflow above about 1e154 (giving inf - inf = NaN) and underflow below
  // 1e-154: outside [1e-150, 1e150] the corners are divided by the largest (the integral scales as
  // 1 / q^2). Inside, the formula is applied as it is, bit for bit.
  if (lo >= 1e-150 && hi <= 1e150) return unscaled_inverse_square_integral(q00, q10, q01, q11);
  const double scaled = unscaled_inverse_square_integral(q00 / hi, q10 / hi, q01 / hi, q11 / hi);
  // NaN is left only where the corners differ by more than 1e154 within one cell: the smallest then
  // dominates an integral beyond any node count.
  if (std::isnan(scaled)) return std::numeric_limits<double>::infinity();
  return scaled / hi / hi;
}

}  // namespace pdmesh
