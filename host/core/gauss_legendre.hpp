// Gauss-Legendre quadrature on [0, 1]: n nodes, exact for polynomials of degree <= 2n - 1.
#pragma once
#include <vector>

namespace pdmesh {

struct QuadratureRule {
  std::vector<double> x;  // nodes in (0, 1), ascending
  std::vector<double> w;  // weights, summing to 1
};

// The roots of the Legendre polynomial P_n by Newton's method from the usual cosine guesses, weights
// 1 / ((1 - z²) P_n'(z)²) on [0, 1]. n >= 1.
QuadratureRule gauss_legendre01(int n);

}  // namespace pdmesh
