// Particles in a metric ("elliptical bubbles"): the per-node and per-pair expressions of metric mode
// (SimParticles::m11, m12, m22), written as kernels would write them (closed forms, no loops).
//
// Node i's size tensor is S_i = M_i^(-1/2) (its bubble: the ellipse S_i * unit disc). A pair is measured
// in the metric of the mean size tensor S_ij = (S_i + S_j) / 2, so rho_ij = |S_ij^-1 d| with d = x_j - x_i.
// Why this mean: with M = I / q^2 it is S_ij = (q_i + q_j) / 2 * I, the isotropic sigma of eq. 5.11,
// for any q (so the metric force reduces to the isotropic one); it is symmetric in i and j (one pair
// distance, antisymmetric forces); and per pair it costs an addition, a 2x2 determinant and an
// adjugate product. Per node it costs two square roots, once per step. A log-Euclidean mean would
// need an eigen-decomposition per pair.
#pragma once
#include <cmath>

namespace pdmesh::reference {

// Upper triangle of a symmetric 2x2 matrix [[a, b], [b, c]].
struct Sym2 {
  double a = 0.0, b = 0.0, c = 0.0;
};

// M^(-1/2) for SPD M = [[m11, m12], [m12, m22]]: with s = sqrt(det M) and t = sqrt(tr M + 2 s),
// M^(1/2) = (M + s I) / t, so M^(-1/2) = adj(M + s I) / (s t).
inline Sym2 size_tensor(double m11, double m12, double m22) {
  const double s = std::sqrt(m11 * m22 - m12 * m12);
  const double t = std::sqrt(m11 + m22 + 2.0 * s);
  const double inv = 1.0 / (s * t);
  return Sym2{(m22 + s) * inv, -m12 * inv, (m11 + s) * inv};
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

// rho^2 = |S^-1 d|^2 for the pair's mean size tensor S = (si + sj) / 2. S^-1 = adj(S) / det S. Since
// |S d| <= |S|_2 |d| and |S|_2 <= (h_i + h_j) / 2 (h the largest sizes), rho <= c implies
// |d| <= c * max(h_i, h_j): the neighbour search's bound.
inline double pair_distance2(const Sym2& si, const Sym2& sj, double dx, double dy) {
  const double a = 0.5 * (si.a + sj.a), b = 0.5 * (si.b + sj.b), c = 0.5 * (si.c + sj.c);
  const double inv_det = 1.0 / (a * c - b * b);
  const double ex = (c * dx - b * dy) * inv_det;
  const double ey = (a * dy - b * dx) * inv_det;
  return ex * ex + ey * ey;
}

// The sign of f^T M_ij d with M_ij = S^-2, S the pair's mean size tensor: > 0 when d lies in the
// half-plane f points into, measured in the pair's metric. (S^-1 f) . (S^-1 d) has the sign of
// (adj S f) . (adj S d), since det S > 0.
inline double pair_metric_dot_sign(const Sym2& si, const Sym2& sj, double fx, double fy, double dx, double dy) {
  const double a = 0.5 * (si.a + sj.a), b = 0.5 * (si.b + sj.b), c = 0.5 * (si.c + sj.c);
  const double ux = c * fx - b * fy, uy = a * fy - b * fx;
  const double vx = c * dx - b * dy, vy = a * dy - b * dx;
  return ux * vx + uy * vy;
}

// |v|_M^2 = v^T M v.
inline double metric_norm2(double m11, double m12, double m22, double vx, double vy) {
  return m11 * vx * vx + 2.0 * m12 * vx * vy + m22 * vy * vy;
}

}  // namespace pdmesh::reference
