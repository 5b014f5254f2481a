// Particles in a metric ("elliptical bubbles"): the per-node and per-pair expressions of metric mode
// (SimParticles::m11, m12, m22), written as kernels would write them (closed forms, no loops).
//
// A pair is measured in the geometric mean of the two nodes' metrics, M_ij = M_i # M_j (the midpoint
// of the geodesic between them in the space of SPD matrices), so rho_ij^2 = d^T M_ij d with
// d = x_j - x_i. For 2x2 matrices it has a closed form with square roots only: with a = sqrt(det M)
// and N = M / a (unit determinant), M_i # M_j = sqrt(a_i a_j) (N_i + N_j) / sqrt(det(N_i + N_j)).
// Why this mean: it lies between the two metrics (it does not let the coarser node's size dominate a
// pair across a steep layer, as the mean of the size tensors M^(-1/2) does, nor the finer one, as the
// mean of the metrics does), it is symmetric in i and j (one pair distance, antisymmetric forces),
// and with M = I / q^2 it is I / (q_i q_j): the isotropic force with sigma = sqrt(q_i q_j), equal to
// eq. 5.11's sigma = (q_i + q_j) / 2 for equal sizes. Square roots and the four operations only, so
// the kernel repeats it bit for bit; per node it costs two square roots, once per step (pair_factor).
#pragma once
#include <cmath>

namespace pdmesh::reference {

// A node's factor of the pair metric: N = M / sqrt(det M) as the upper triangle [[a, b], [b, c]], and
// w = (det M)^(1/4).
struct Sym2 {
  double a = 0.0, b = 0.0, c = 0.0, w = 0.0;
};

// The pair factor of SPD M = [[m11, m12], [m12, m22]] (see above).
inline Sym2 pair_factor(double m11, double m12, double m22) {
  const double s = std::sqrt(m11 * m22 - m12 * m12);
  const double inv = 1.0 / s;
  return Sym2{m11 * inv, m12 * inv, m22 * inv, std::sqrt(s)};
}

// A node's size tensor S = M^(-1/2) as the upper triangle [[a, b], [b, c]]: its bubble is the ellipse
// S * unit disc (the study tools kick nodes by S times a random vector).
struct SizeTensor {
  double a = 0.0, b = 0.0, c = 0.0;
};

// With s = sqrt(det M) and t = sqrt(tr M + 2 s), M^(1/2) = (M + s I) / t, so M^(-1/2) = adj(M + s I) / (s t).
inline SizeTensor size_tensor(double m11, double m12, double m22) {
  const double s = std::sqrt(m11 * m22 - m12 * m12);
  const double t = std::sqrt(m11 + m22 + 2.0 * s);
  const double inv = 1.0 / (s * t);
  return SizeTensor{(m22 + s) * inv, -m12 * inv, (m11 + s) * inv};
}

// The largest size of a metric, 1 / sqrt(lambda_min) = sqrt(lambda_max / det): the half-axis of the
// bubble's long side, which bounds |d| for every pair within metric distance 1 (see pair_distance2).
inline double largest_size(double m11, double m12, double m22) {
  const double half_tr = 0.5 * (m11 + m22);
  const double h = 0.5 * (m11 - m22);
  const double lmax = half_tr + std::sqrt(h * h + m12 * m12);
  return std::sqrt(lmax / (m11 * m22 - m12 * m12));
}

// Finite and positive definite (m11 > 0 and det > 0), as the metric of a valid node must be.
inline bool valid_metric(double m11, double m12, double m22) {
  return std::isfinite(m11) && std::isfinite(m12) && std::isfinite(m22) && m11 > 0.0 && m11 * m22 - m12 * m12 > 0.0;
}

// rho^2 = d^T (M_i # M_j) d = w_i w_j (d^T G d) / sqrt(det G), G = N_i + N_j. The geometric mean is
// at least the harmonic mean 2 (M_i^-1 + M_j^-1)^-1, whose inverse has largest eigenvalue at most
// (h_i^2 + h_j^2) / 2 (h the largest sizes), so rho <= c implies |d| <= c * max(h_i, h_j): the
// neighbour search's bound.
inline double pair_distance2(const Sym2& si, const Sym2& sj, double dx, double dy) {
  const double a = si.a + sj.a, b = si.b + sj.b, c = si.c + sj.c;
  const double dgd = a * dx * dx + 2.0 * b * dx * dy + c * dy * dy;
  return si.w * sj.w * dgd / std::sqrt(a * c - b * b);
}

// The sign of f^T M_ij d: > 0 when d lies in the half-plane f points into, measured in the pair's
// metric. M_ij is a positive multiple of G = N_i + N_j, so f^T G d has its sign.
inline double pair_metric_dot_sign(const Sym2& si, const Sym2& sj, double fx, double fy, double dx, double dy) {
  const double a = si.a + sj.a, b = si.b + sj.b, c = si.c + sj.c;
  return (a * fx + b * fy) * dx + (b * fx + c * fy) * dy;
}

// |v|_M^2 = v^T M v.
inline double metric_norm2(double m11, double m12, double m22, double vx, double vy) {
  return m11 * vx * vx + 2.0 * m12 * vx * vy + m22 * vy * vy;
}

}  // namespace pdmesh::reference
