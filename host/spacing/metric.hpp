// A 2-D Riemannian metric: a symmetric positive-definite 2x2 matrix M = [[m11, m12], [m12, m22]]
// that measures a vector v as sqrt(vᵀ M v). Sizes h1 along a direction and h2 across it give
// M = R diag(1/h1², 1/h2²) Rᵀ (R the rotation by the direction's angle); a mesh whose every edge has
// length 1 in M (the "unit mesh") has edges of h1 along the direction and h2 across it.
// The operations of metric-based adaptation (Loseille-Alauzet's continuous mesh): the eigen-
// decomposition, lengths along an edge, log-Euclidean interpolation, intersection by simultaneous
// reduction, and the growth a metric allows along an edge (Alauzet's gradation). See docs/metric-fields.md.
#pragma once
#include <string_view>
#include <vector>

#include "core/vec2.hpp"

namespace pdmesh {

struct Metric {
  double m11 = 1.0;
  double m12 = 0.0;
  double m22 = 1.0;

  double det() const { return m11 * m22 - m12 * m12; }
  // vᵀ M v and its root, the length of v in M.
  double quad(Vec2 v) const { return m11 * v.x * v.x + 2.0 * m12 * v.x * v.y + m22 * v.y * v.y; }
  double length(Vec2 v) const;
};

inline Metric operator*(double s, const Metric& m) { return {s * m.m11, s * m.m12, s * m.m22}; }
inline Metric operator+(const Metric& a, const Metric& b) { return {a.m11 + b.m11, a.m12 + b.m12, a.m22 + b.m22}; }

// M = R diag(1/h1², 1/h2²) Rᵀ: size h1 along (cos angle, sin angle), h2 across it. Angle in radians.
// Unchecked; see check_sizes.
Metric metric_from_sizes(double h1, double h2, double angle);

// M = R diag(lambda1, lambda2) Rᵀ with lambda1 along (cos angle, sin angle).
Metric metric_from_eigen(double lambda1, double lambda2, double angle);

// The eigen-decomposition of a symmetric 2x2 matrix: lambda1 >= lambda2, lambda1's unit eigenvector
// (cos angle, sin angle) with angle in (-pi/2, pi/2]; lambda2's is that turned by +90 degrees.
// For a metric the sizes are 1/sqrt(lambda): h = 1/sqrt(lambda1) is the smaller one.
struct MetricEigen {
  double lambda1 = 1.0;
  double lambda2 = 1.0;
  double angle = 0.0;
  Vec2 v1() const;
  Vec2 v2() const;
};
MetricEigen eigen(const Metric& m);

// Throws InputError naming `what` and the value unless h1 and h2 are finite and positive and the
// angle is finite.
void check_sizes(double h1, double h2, double angle, std::string_view what);
// Throws InputError naming `what` and the three components unless M is finite and positive
// definite (m11 > 0 and det > 0, computed so that no finite input overflows to a wrong answer).
void check_metric(const Metric& m, std::string_view what);
// True when check_metric would accept m.
bool is_spd(const Metric& m);

// The length of the edge v between two points whose metrics are ma and mb, with the metric
// interpolated along it so that its length element varies geometrically from La = |v|_ma to
// Lb = |v|_mb (Loseille-Alauzet): L = (La - Lb) / ln(La / Lb), and (La + Lb)/2 when
// |La - Lb| <= 1e-3 (where the formula loses digits). The UGAWG measure (tools/eval metric.py).
double edge_length(const Metric& ma, const Metric& mb, Vec2 v);

// The same length by Gauss-Legendre quadrature (n points) of |v|_M(t) along the edge, with M(t) the
// log-Euclidean interpolation of ma and mb (interpolate below). When mb is a multiple of ma the
// length element is exactly geometric along the edge, and the two agree to the quadrature's accuracy.
double edge_length_quadrature(const Metric& ma, const Metric& mb, Vec2 v, int n = 8);

// Matrix logarithm and exponential of symmetric matrices through the eigen-decomposition: log needs
// an SPD matrix; exp gives one.
Metric log_metric(const Metric& m);
Metric exp_metric(const Metric& m);

// Log-Euclidean interpolation: exp((1 - t) log ma + t log mb). SPD for any t, equal to ma at t = 0
// and mb at t = 1, and ma when ma == mb.
Metric interpolate(const Metric& ma, const Metric& mb, double t);
// The log-Euclidean mean exp(sum w_i log M_i / sum w_i); weights non-negative, not all zero.
Metric log_euclidean_mean(const std::vector<Metric>& m, const std::vector<double>& w);

// The intersection of two metrics by simultaneous reduction: the largest metric (smallest sizes) in
// every direction of the common eigenbasis of a and b, so that |v|_result >= max(|v|_a, |v|_b)
// up to rounding, with equality along the two common eigenvectors. Computed in the basis
// a^(-1/2) b a^(-1/2), which keeps every step symmetric.
Metric intersect(const Metric& a, const Metric& b);
// The largest ratio |v|_b² / |v|_a² over all directions v: the largest eigenvalue of a⁻¹b (1 or less:
// b asks for no smaller size than a in any direction).
double largest_metric_ratio(const Metric& a, const Metric& b);

// Metric gradation (Alauzet 2010, "Size gradation control of anisotropic meshes"; the mixed form of
// Alauzet & Frazza 2021). span_metric(m, v, beta, t) is the metric that m at one end of v lets the
// other end have: each eigenvalue lambda_i of m divided by eta_i², with
//   eta_i = (1 + |v|_m ln beta)^(1 - t) * (1 + sqrt(lambda_i) |v| ln beta)^t.
// t = 0 grows both sizes in proportion (metric space: the shape of m is kept), t = 1 grows each size
// by |v| ln beta (physical space), and t in between mixes the two.
Metric span_metric(const Metric& m, Vec2 v, double beta, double t);
// The gradation of an edge v between metrics ma and mb: the size ratio per unit of metric length,
// max(a, 1/a)^(1/L) with a = |v|_ma / |v|_mb and L the edge's metric length when the size along v
// varies linearly from one end to the other, as span_metric's growth does: span_metric(m, v, beta, 0)
// at the far end has gradation beta exactly along v. 1 when the two agree along v.
double edge_gradation(const Metric& ma, const Metric& mb, Vec2 v);

}  // namespace pdmesh
