// The 2x2 metric algebra (metric.hpp): closed-form symmetric eigen-decomposition, matrix functions
// through it, lengths, interpolation, intersection and gradation.
#include "spacing/metric.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "core/errors.hpp"
#include "core/gauss_legendre.hpp"

namespace pdmesh {

namespace {

// f applied to the eigenvalues: R diag(f(lambda1), f(lambda2)) Rᵀ.
template <class F>
Metric apply(const Metric& m, F f) {
  const MetricEigen e = eigen(m);
  return metric_from_eigen(f(e.lambda1), f(e.lambda2), e.angle);
}

}  // namespace

double Metric::length(Vec2 v) const { return std::sqrt(std::max(quad(v), 0.0)); }

Vec2 MetricEigen::v1() const { return {std::cos(angle), std::sin(angle)}; }
Vec2 MetricEigen::v2() const { return {-std::sin(angle), std::cos(angle)}; }

Metric metric_from_eigen(double lambda1, double lambda2, double angle) {
  const double c = std::cos(angle), s = std::sin(angle);
  return {lambda1 * c * c + lambda2 * s * s, (lambda1 - lambda2) * c * s, lambda1 * s * s + lambda2 * c * c};
}

Metric metric_from_sizes(double h1, double h2, double angle) {
  return metric_from_eigen(1.0 / (h1 * h1), 1.0 / (h2 * h2), angle);
}

MetricEigen eigen(const Metric& m) {
  // lambda = mean ± r with r = |((m11 - m22)/2, m12)|; the smaller one as det / lambda1 when both
  // have one sign, which keeps its relative accuracy when the metric is very anisotropic.
  const double mean = 0.5 * (m.m11 + m.m22);
  const double half_diff = 0.5 * (m.m11 - m.m22);
  const double r = std::hypot(half_diff, m.m12);
  MetricEigen e;
  e.lambda1 = mean + r;
  const double det = m.det();
  e.lambda2 = (e.lambda1 > 0.0 && det > 0.0) ? det / e.lambda1 : mean - r;
  e.angle = (r == 0.0) ? 0.0 : 0.5 * std::atan2(m.m12, half_diff);
  return e;
}

bool is_spd(const Metric& m) {
  if (!std::isfinite(m.m11) || !std::isfinite(m.m12) || !std::isfinite(m.m22)) return false;
  if (!(m.m11 > 0.0) || !(m.m22 > 0.0)) return false;
  // m11 m22 > m12² as sqrt(m11) sqrt(m22) > |m12|, which no finite input overflows.
  return std::sqrt(m.m11) * std::sqrt(m.m22) > std::fabs(m.m12);
}

void check_sizes(double h1, double h2, double angle, std::string_view what) {
  if (!std::isfinite(h1) || h1 <= 0.0)
    throw InputError(fmt::format("{}: size h1 = {} must be a finite positive number", what, h1));
  if (!std::isfinite(h2) || h2 <= 0.0)
    throw InputError(fmt::format("{}: size h2 = {} must be a finite positive number", what, h2));
  if (!std::isfinite(angle)) throw InputError(fmt::format("{}: angle = {} must be a finite number", what, angle));
}

void check_metric(const Metric& m, std::string_view what) {
  if (is_spd(m)) return;
  if (!std::isfinite(m.m11) || !std::isfinite(m.m12) || !std::isfinite(m.m22))
    throw InputError(fmt::format("{}: metric (m11, m12, m22) = ({}, {}, {}) is not finite", what, m.m11, m.m12, m.m22));
  throw InputError(
      fmt::format("{}: metric (m11, m12, m22) = ({}, {}, {}) is not positive definite "
                  "(needs m11 > 0, m22 > 0 and m11*m22 - m12^2 = {} > 0)",
                  what, m.m11, m.m12, m.m22, m.det()));
}

double edge_length(const Metric& ma, const Metric& mb, Vec2 v) {
  const double la = ma.length(v), lb = mb.length(v);
  if (std::fabs(la - lb) <= 1e-3) return 0.5 * (la + lb);
  return (la - lb) / std::log(la / lb);
}

double edge_length_quadrature(const Metric& ma, const Metric& mb, Vec2 v, int n) {
  const QuadratureRule rule = gauss_legendre01(n);
  const Metric la = log_metric(ma), lb = log_metric(mb);
  double sum = 0.0;
  for (std::size_t i = 0; i < rule.x.size(); ++i)
    sum += rule.w[i] * exp_metric((1.0 - rule.x[i]) * la + rule.x[i] * lb).length(v);
  return sum;
}

Metric log_metric(const Metric& m) {
  return apply(m, [](double l) { return std::log(l); });
}

Metric exp_metric(const Metric& m) {
  return apply(m, [](double l) { return std::exp(l); });
}

Metric interpolate(const Metric& ma, const Metric& mb, double t) {
  return exp_metric((1.0 - t) * log_metric(ma) + t * log_metric(mb));
}

Metric log_euclidean_mean(const std::vector<Metric>& m, const std::vector<double>& w) {
  Metric sum{0.0, 0.0, 0.0};
  double total = 0.0;
  for (std::size_t i = 0; i < m.size() && i < w.size(); ++i) {
    if (w[i] == 0.0) continue;
    sum = sum + w[i] * log_metric(m[i]);
    total += w[i];
  }
  return exp_metric((1.0 / total) * sum);
}

Metric intersect(const Metric& a, const Metric& b) {
  // With S = a^(1/2) and N = S^-1 b S^-1 = Q diag(s) Qᵀ: a = S I S and b = S N S, so in the basis
  // S^-1 Q both are diagonal (1 and s); the intersection keeps max(1, s_i) there.
  const MetricEigen ea = eigen(a);
  const double ra1 = std::sqrt(ea.lambda1), ra2 = std::sqrt(ea.lambda2);
  const Metric s = metric_from_eigen(ra1, ra2, ea.angle);
  const Metric s_inv = metric_from_eigen(1.0 / ra1, 1.0 / ra2, ea.angle);
  // N = S^-1 b S^-1, with the symmetric products written out.
  const double t11 = s_inv.m11 * b.m11 + s_inv.m12 * b.m12, t12 = s_inv.m11 * b.m12 + s_inv.m12 * b.m22;
  const double t21 = s_inv.m12 * b.m11 + s_inv.m22 * b.m12, t22 = s_inv.m12 * b.m12 + s_inv.m22 * b.m22;
  const Metric n{t11 * s_inv.m11 + t12 * s_inv.m12,
                 0.5 * (t11 * s_inv.m12 + t12 * s_inv.m22 + t21 * s_inv.m11 + t22 * s_inv.m12),
                 t21 * s_inv.m12 + t22 * s_inv.m22};
  const MetricEigen en = eigen(n);
  const Metric k = metric_from_eigen(std::max(1.0, en.lambda1), std::max(1.0, en.lambda2), en.angle);
  // result = S K S.
  const double u11 = s.m11 * k.m11 + s.m12 * k.m12, u12 = s.m11 * k.m12 + s.m12 * k.m22;
  const double u21 = s.m12 * k.m11 + s.m22 * k.m12, u22 = s.m12 * k.m12 + s.m22 * k.m22;
  return {u11 * s.m11 + u12 * s.m12, 0.5 * (u11 * s.m12 + u12 * s.m22 + u21 * s.m11 + u22 * s.m12),
          u21 * s.m12 + u22 * s.m22};
}

double largest_metric_ratio(const Metric& a, const Metric& b) {
  // The roots of det(b - l a) = 0: det(a) l² - t l + det(b) = 0 with t = tr(adj(a) b).
  const double t = a.m22 * b.m11 + a.m11 * b.m22 - 2.0 * a.m12 * b.m12;
  const double da = a.det();
  const double disc = std::max(0.0, t * t - 4.0 * da * b.det());
  return (t + std::sqrt(disc)) / (2.0 * da);
}

Metric span_metric(const Metric& m, Vec2 v, double beta, double t) {
  const double log_beta = std::log(beta);
  const double eta0 = std::pow(1.0 + m.length(v) * log_beta, 1.0 - t);
  const double physical = norm(v) * log_beta;
  return apply(m, [&](double lambda) {
    const double eta = eta0 * std::pow(1.0 + std::sqrt(lambda) * physical, t);
    return lambda / (eta * eta);
  });
}

double edge_gradation(const Metric& ma, const Metric& mb, Vec2 v) {
  const double la = ma.length(v), lb = mb.length(v);
  const double a = la / lb;
  // The edge's length with the size varying linearly along it: L = |v| ln(hb/ha) / (hb - ha) with
  // h = |v| / l at each end, i.e. la lb ln(la/lb) / (la - lb); la when the two agree.
  const double l = std::fabs(a - 1.0) < 1e-9 ? la : la * lb * std::log(a) / (la - lb);
  return std::pow(std::max(a, 1.0 / a), 1.0 / l);
}

}  // namespace pdmesh
