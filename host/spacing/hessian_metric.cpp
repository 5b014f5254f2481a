// The L^p-optimal metric from Hessians of a function or of mesh data (hessian_metric.hpp).
#include "spacing/hessian_metric.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>

#include "core/errors.hpp"
#include "core/parallel.hpp"
#include "spacing/spacing_field.hpp"

namespace pdmesh {

void check_hessian_metric_options(const HessianMetricOptions& o) {
  if (!std::isfinite(o.complexity) || !(o.complexity > 0.0))
    throw InputError(fmt::format("hessian metric: complexity = {} must be a finite positive number", o.complexity));
  if (!std::isfinite(o.p) || !(o.p >= 1.0))
    throw InputError(fmt::format("hessian metric: p = {} must be a finite number >= 1", o.p));
  if (!(o.hmin >= 0.0) || !std::isfinite(o.hmin))
    throw InputError(fmt::format("hessian metric: hmin = {} must be a finite number >= 0", o.hmin));
  if (!(o.hmax > o.hmin))
    throw InputError(fmt::format("hessian metric: hmax = {} must be larger than hmin = {}", o.hmax, o.hmin));
  if (!(o.max_anisotropy >= 1.0))
    throw InputError(fmt::format("hessian metric: max_anisotropy = {} must be >= 1", o.max_anisotropy));
  if (!std::isfinite(o.floor) || !(o.floor > 0.0))
    throw InputError(fmt::format("hessian metric: floor = {} must be a finite positive number", o.floor));
}

Metric abs_hessian(const Hessian& h, double floor) {
  const MetricEigen e = eigen(Metric{h.xx, h.xy, h.yy});
  return metric_from_eigen(std::max(std::fabs(e.lambda1), floor), std::max(std::fabs(e.lambda2), floor), e.angle);
}

double hessian_density(const Hessian& h, const HessianMetricOptions& o) {
  return std::pow(abs_hessian(h, o.floor).det(), o.p / (2.0 * o.p + 2.0));
}

Metric clip_metric(const Metric& m, double hmin, double hmax, double max_anisotropy) {
  const MetricEigen e = eigen(m);
  const double lo = 1.0 / (hmax * hmax);
  const double hi = hmin > 0.0 ? 1.0 / (hmin * hmin) : std::numeric_limits<double>::infinity();
  const double l1 = std::clamp(e.lambda1, lo, hi);
  double l2 = std::clamp(e.lambda2, lo, hi);
  if (std::isfinite(max_anisotropy)) l2 = std::max(l2, l1 / (max_anisotropy * max_anisotropy));
  return metric_from_eigen(l1, l2, e.angle);
}

Metric lp_optimal_metric(const Hessian& h, double scale, const HessianMetricOptions& o) {
  const Metric a = abs_hessian(h, o.floor);
  const Metric m = (scale * std::pow(a.det(), -1.0 / (2.0 * o.p + 2.0))) * a;
  return clip_metric(m, o.hmin, o.hmax, o.max_anisotropy);
}

namespace {

// C / ∫ density by the P1 rule on the triangles (the mean of the corners times the area).
double density_scale(const std::vector<Vec2>& points, const std::vector<std::array<int, 3>>& triangles,
                     const std::vector<double>& density, double complexity, std::string_view what) {
  double integral = 0.0;
  for (const auto& t : triangles) {
    const double area = 0.5 * std::fabs(cross(points[t[1]] - points[t[0]], points[t[2]] - points[t[0]]));
    integral += area * (density[t[0]] + density[t[1]] + density[t[2]]) / 3.0;
  }
  if (!(integral > 0.0))
    throw InputError(fmt::format("{}: the mesh has no area to spread complexity {} over", what, complexity));
  return complexity / integral;
}

}  // namespace

std::vector<Metric> hessian_metrics_on_mesh(const std::vector<Vec2>& points,
                                            const std::vector<std::array<int, 3>>& triangles,
                                            const std::vector<double>& u, const HessianMetricOptions& o,
                                            std::string_view what) {
  check_hessian_metric_options(o);
  const std::vector<Hessian> h = recover_hessians(points, triangles, u, what);
  std::vector<double> density(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) density[i] = hessian_density(h[i], o);
  const double scale = density_scale(points, triangles, density, o.complexity, what);
  std::vector<Metric> m(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) m[i] = lp_optimal_metric(h[i], scale, o);
  return m;
}

Metric lp_unscaled_metric(const Hessian& h, const HessianMetricOptions& o) {
  const Metric a = abs_hessian(h, o.floor);
  return std::pow(a.det(), -1.0 / (2.0 * o.p + 2.0)) * a;
}

double complexity_scale(const std::vector<Vec2>& points, const std::vector<std::array<int, 3>>& triangles,
                        const std::vector<Metric>& m, double complexity, std::string_view what) {
  std::vector<double> density(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) density[i] = std::sqrt(m[i].det());
  return density_scale(points, triangles, density, complexity, what);
}

std::vector<double> divided_by_range(const std::vector<double>& u) {
  if (u.empty()) return {};
  const auto [lo, hi] = std::minmax_element(u.begin(), u.end());
  const double range = *hi - *lo;
  const double by = range > 0.0 ? range : 1.0;
  std::vector<double> out(u.size());
  for (std::size_t i = 0; i < u.size(); ++i) out[i] = u[i] / by;
  return out;
}

std::vector<Metric> intersected_hessian_metrics_on_mesh(const std::vector<Vec2>& points,
                                                        const std::vector<std::array<int, 3>>& triangles,
                                                        const std::vector<std::vector<double>>& arrays,
                                                        const HessianMetricOptions& o,
                                                        const std::vector<std::string>& what) {
  if (arrays.empty() || what.size() != arrays.size())
    throw InputError(fmt::format("hessian metric: {} arrays with {} names", arrays.size(), what.size()));
  if (arrays.size() == 1) return hessian_metrics_on_mesh(points, triangles, arrays[0], o, what[0]);
  check_hessian_metric_options(o);
  std::vector<Metric> m(points.size());
  for (std::size_t k = 0; k < arrays.size(); ++k) {
    const std::vector<Hessian> h = recover_hessians(points, triangles, divided_by_range(arrays[k]), what[k]);
    for (std::size_t i = 0; i < points.size(); ++i) {
      const Metric mk = lp_unscaled_metric(h[i], o);
      m[i] = k == 0 ? mk : intersect(m[i], mk);
    }
  }
  const double scale = complexity_scale(points, triangles, m, o.complexity, fmt::format("{}", fmt::join(what, ", ")));
  for (Metric& mi : m) mi = clip_metric(scale * mi, o.hmin, o.hmax, o.max_anisotropy);
  return m;
}

HessianMetricField::HessianMetricField(const std::string& expression, const Box& box, const HessianMetricOptions& o,
                                       double step, int grid)
    : u_(expression),
      parsers_([expression] { return std::make_unique<ScalarExpression>(expression); }),
      options_(o),
      step_(step) {
  check_hessian_metric_options(o);
  if (!std::isfinite(step) || !(step > 0.0))
    throw InputError(
        fmt::format("hessian metric of '{}': step = {} must be a finite positive number", expression, step));
  if (!(box.width() > 0.0) || !(box.height() > 0.0) || grid < 1)
    throw InputError(fmt::format("hessian metric of '{}': an empty box or grid ({})", expression, grid));
  // The cells' densities on all threads, then their sum in row order, as one thread would add them.
  const std::size_t side = static_cast<std::size_t>(grid);
  std::vector<double> density(side * side);
  parallel_for_scratch<LeasePool<ScalarExpression>::Lease>(
      density.size(),
      [&](LeasePool<ScalarExpression>::Lease& u, std::size_t c) {
        if (!u) u = parsers_.take();
        const double i = static_cast<double>(c % side), j = static_cast<double>(c / side);
        const Vec2 p{box.lo.x + (i + 0.5) / grid * box.width(), box.lo.y + (j + 0.5) / grid * box.height()};
        density[c] = hessian_density(hessian_by_differences([&u](Vec2 q) { return (*u)(q); }, p, step_), options_);
      },
      kExpressionPointsPerThread);
  double total = 0.0;
  for (const double d : density) total += d;
  const double integral = total * box.width() * box.height() / (static_cast<double>(grid) * grid);
  scale_ = options_.complexity / integral;
}

Hessian HessianMetricField::hessian(Vec2 p) const {
  return hessian_by_differences([this](Vec2 q) { return u_(q); }, p, step_);
}

Metric HessianMetricField::at(Vec2 p) const { return lp_optimal_metric(hessian(p), scale_, options_); }

void HessianMetricField::at_many(const std::vector<Vec2>& p, std::vector<Metric>& out,
                                 std::vector<int>& guesses) const {
  out.resize(p.size());
  guesses.resize(p.size());
  parallel_for_scratch<LeasePool<ScalarExpression>::Lease>(
      p.size(),
      [&](LeasePool<ScalarExpression>::Lease& u, std::size_t i) {
        if (!u) u = parsers_.take();
        const Hessian h = hessian_by_differences([&u](Vec2 q) { return (*u)(q); }, p[i], step_);
        out[i] = lp_optimal_metric(h, scale_, options_);
      },
      kExpressionPointsPerThread);
}

void sample_metric_grid(const MetricField& field, const Box& box, int n, std::vector<Vec2>& points,
                        std::vector<std::array<int, 3>>& triangles, std::vector<Metric>& metrics) {
  if (n < 1) throw InputError(fmt::format("sample_metric_grid: n = {} must be >= 1", n));
  const double dx = box.width() / n, dy = box.height() / n;
  const int row = n + 1;
  points.clear();
  triangles.clear();
  metrics.clear();
  // n + 1 points per row from lo - d/2 to hi + d/2.
  const double sx = (box.width() + dx) / n, sy = (box.height() + dy) / n;
  points.reserve(static_cast<std::size_t>(row) * row);
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) points.push_back({box.lo.x - 0.5 * dx + i * sx, box.lo.y - 0.5 * dy + j * sy});
  triangles.reserve(2 * static_cast<std::size_t>(n) * n);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const int a = j * row + i;
      triangles.push_back({a, a + 1, a + row + 1});
      triangles.push_back({a, a + row + 1, a + row});
    }
  std::vector<int> guesses;
  field.at_many(points, metrics, guesses);
}

}  // namespace pdmesh
