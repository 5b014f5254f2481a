// Lawson flips in a metric field: the in-circle test in the log-Euclidean mean metric of each
// quadrilateral, physical validity by the exact orient2d, a bound on the flips.
#include "mesh/metric_delaunay.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "core/errors.hpp"
#include "core/interrupt.hpp"
#include "core/predicates.hpp"
#include "mesh/triangle_corners.hpp"

namespace pdmesh {
namespace {

// |vᵀ M| v with every term taken by its magnitude: the bound on vᵀMv's rounding.
double abs_quad(const Metric& m, Vec2 v) {
  return std::fabs(m.m11) * v.x * v.x + 2.0 * std::fabs(m.m12 * v.x * v.y) + std::fabs(m.m22) * v.y * v.y;
}

// The metric of a quadrilateral: exp of the mean of its vertices' log metrics, summed in vertex
// order so that the same four vertices give the same metric bit for bit, whichever edge is tested.
class QuadMetric {
 public:
  QuadMetric(const Triangulation& tri, const std::vector<Metric>& metrics) {
    if (metrics.size() != static_cast<std::size_t>(tri.input_count)) {
      throw InputError(fmt::format("metric Delaunay: {} metrics for {} points", metrics.size(), tri.input_count));
    }
    logs_.resize(static_cast<std::size_t>(tri.input_count));
    for (int k = 0; k < tri.input_count; ++k) {
      const int i = tri.input_index[static_cast<std::size_t>(k)];
      const Vec2 p = tri.points[static_cast<std::size_t>(k)];
      const Metric& m = metrics[static_cast<std::size_t>(i)];
      if (!is_spd(m)) check_metric(m, fmt::format("metric Delaunay: point {} ({}, {})", i, p.x, p.y));
      logs_[static_cast<std::size_t>(k)] = log_metric(m);
    }
  }

  Metric at(int p, int a, int b, int q) const {
    std::array<int, 4> v{p, a, b, q};
    std::sort(v.begin(), v.end());
    Metric sum = logs_[static_cast<std::size_t>(v[0])];
    for (int k = 1; k < 4; ++k) sum = sum + logs_[static_cast<std::size_t>(v[k])];
    return exp_metric(0.25 * sum);
  }

 private:
  std::vector<Metric> logs_;  // per vertex of the triangulation (input points only)
};

// Whether the edge opposite v[t][i] may flip and the metric asks for it (see the header).
bool flip_wanted(const Triangulation& tri, const QuadMetric& qm, int t, int i, std::size_t& tests) {
  const int u = tri.n[t][i];
  if (u < 0) return false;
  const int p = tri.v[t][i], a = tri.v[t][next3(i)], b = tri.v[t][prev3(i)];
  const int q = tri.v[u][index_of(tri.n[u], t)];
  if (tri.is_super(p) || tri.is_super(a) || tri.is_super(b) || tri.is_super(q)) return false;
  if (tri.is_constrained(a, b)) return false;
  const auto& P = tri.points;
  if (!(orient2d(P[p], P[a], P[q]) > 0.0) || !(orient2d(P[q], P[b], P[p]) > 0.0)) return false;
  ++tests;
  return metric_incircle(P[p], P[a], P[b], P[q], qm.at(p, a, b, q)) > 0;
}

}  // namespace

int metric_incircle(Vec2 a, Vec2 b, Vec2 c, Vec2 d, const Metric& m) {
  const Vec2 u = a - d, v = b - d, w = c - d;
  const double cu = v.x * w.y - v.y * w.x, cv = w.x * u.y - w.y * u.x, cw = u.x * v.y - u.y * v.x;
  const double det = m.quad(u) * cu + m.quad(v) * cv + m.quad(w) * cw;
  const double bound = abs_quad(m, u) * (std::fabs(v.x * w.y) + std::fabs(v.y * w.x)) +
                       abs_quad(m, v) * (std::fabs(w.x * u.y) + std::fabs(w.y * u.x)) +
                       abs_quad(m, w) * (std::fabs(u.x * v.y) + std::fabs(u.y * v.x));
  const double tie = kMetricIncircleTie * bound;
  if (det > tie) return 1;
  if (det < -tie) return -1;
  return 0;
}

MetricDelaunayStats make_metric_delaunay(Triangulation& tri, const std::vector<Metric>& metrics,
                                         const MetricDelaunayOptions& options) {
  const QuadMetric qm(tri, metrics);
  MetricDelaunayStats stats;
  std::vector<std::array<int, 2>> stack;  // edges as (a, b) vertex pairs: triangles change under us
  for (int t = 0; t < static_cast<int>(tri.v.size()); ++t)
    for (int i = 0; i < 3; ++i)
      if (tri.n[t][i] > t) stack.push_back({tri.v[t][next3(i)], tri.v[t][prev3(i)]});
  stats.max_flips = options.max_flips > 0 ? options.max_flips : kMetricFlipsPerEdge * stack.size() + 1000;
  InterruptPoll poll(16384);
  while (!stack.empty()) {
    poll.tick();
    const auto [a, b] = stack.back();
    stack.pop_back();
    const auto [t, i] = tri.find_edge(a, b);
    if (t < 0) continue;  // flipped away meanwhile; its replacement was pushed then
    if (!flip_wanted(tri, qm, t, i, stats.tests)) continue;
    if (stats.flips == stats.max_flips) {
      stats.converged = false;
      break;
    }
    const int u = tri.n[t][i];
    const int p = tri.v[t][i];
    const int q = tri.v[u][index_of(tri.n[u], t)];
    tri.flip(t, i);
    ++stats.flips;
    stack.push_back({p, a});
    stack.push_back({a, q});
    stack.push_back({q, b});
    stack.push_back({b, p});
  }
  return stats;
}

std::vector<std::array<int, 2>> metric_delaunay_violations(const Triangulation& tri,
                                                           const std::vector<Metric>& metrics) {
  const QuadMetric qm(tri, metrics);
  std::vector<std::array<int, 2>> out;
  std::size_t tests = 0;
  for (int t = 0; t < static_cast<int>(tri.v.size()); ++t)
    for (int i = 0; i < 3; ++i)
      if (tri.n[t][i] > t && flip_wanted(tri, qm, t, i, tests))
        out.push_back({tri.input_index[static_cast<std::size_t>(tri.v[t][next3(i)])],
                       tri.input_index[static_cast<std::size_t>(tri.v[t][prev3(i)])]});
  return out;
}

}  // namespace pdmesh
