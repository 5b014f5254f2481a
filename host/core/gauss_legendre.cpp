// Gauss-Legendre nodes and weights by Newton's method on the three-term recurrence (gauss_legendre.hpp).
#include "core/gauss_legendre.hpp"

#include <algorithm>
#include <cmath>

namespace pdmesh {

QuadratureRule gauss_legendre01(int n) {
  n = std::max(n, 1);
  QuadratureRule rule;
  rule.x.resize(n);
  rule.w.resize(n);
  for (int i = 0; i < n; ++i) {
    double z = std::cos(M_PI * (i + 0.75) / (n + 0.5));
    double dp = 1.0;
    for (int it = 0; it < 100; ++it) {
      double p0 = 1.0, p1 = z;  // P_0, P_1, then P_{k-1}, P_k
      for (int k = 2; k <= n; ++k) {
        const double p2 = ((2.0 * k - 1.0) * z * p1 - (k - 1.0) * p0) / k;
        p0 = p1;
        p1 = p2;
      }
      dp = n * (z * p1 - p0) / (z * z - 1.0);
      const double dz = p1 / dp;
      z -= dz;
      if (std::fabs(dz) <= 1e-15) break;
    }
    // Descending z maps to ascending x.
    rule.x[i] = 0.5 * (1.0 - z);
    rule.w[i] = 1.0 / ((1.0 - z * z) * dp * dp);
  }
  return rule;
}

}  // namespace pdmesh
