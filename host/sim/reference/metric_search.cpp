// The frame and box search of metric_search.hpp.
#include "sim/reference/metric_search.hpp"

#include <algorithm>
#include <cmath>

namespace pdmesh::reference {

MetricFrame MetricFrame::of(const SimParticles& p, const std::vector<Sym2>& s) {
  // u along the leading eigenvector of the sum of the shapes N (a sum in node order).
  double sa = 0.0, sb = 0.0, sc = 0.0, extent = 0.0;
  for (std::size_t j = 0; j < p.size(); ++j) {
    sa += s[j].a;
    sb += s[j].b;
    sc += s[j].c;
    extent = std::max({extent, std::abs(p.x[j]), std::abs(p.y[j])});
  }
  const double angle = 0.5 * std::atan2(2.0 * sb, sa - sc);
  return MetricFrame{std::cos(angle), std::sin(angle), 1e-12 * (1.0 + extent)};
}

void MetricFrame::half_extents(double m11, double m12, double m22, double cutoff, double& hu, double& hv) const {
  constexpr double kWiden = 1.0 + 1e-9;
  const double det = m11 * m22 - m12 * m12;
  // e^T M^-1 e with M^-1 = [[m22, -m12], [-m12, m11]] / det, e = (cs, sn) and (-sn, cs).
  const double wu = (m22 * cs * cs - 2.0 * m12 * cs * sn + m11 * sn * sn) / det;
  const double wv = (m22 * sn * sn + 2.0 * m12 * cs * sn + m11 * cs * cs) / det;
  hu = kWiden * cutoff * std::sqrt(std::max(wu, 0.0)) + slack;
  hv = kWiden * cutoff * std::sqrt(std::max(wv, 0.0)) + slack;
}

void MetricBoxSearch::build(const SimParticles& p, const MetricFrame& frame, double cutoff, double reach) {
  const std::size_t n = p.size();
  u_.resize(n);
  v_.resize(n);
  half_u_.resize(n);
  half_v_.resize(n);
  for (std::size_t j = 0; j < n; ++j) {
    u_[j] = frame.u(p.x[j], p.y[j]);
    v_[j] = frame.v(p.x[j], p.y[j]);
    frame.half_extents(p.m11[j], p.m12[j], p.m22[j], cutoff, half_u_[j], half_v_[j]);
    half_u_[j] *= reach;
    half_v_[j] *= reach;
  }
  double u_min = HUGE_VAL;
  for (std::size_t j = 0; j < n; ++j) u_min = std::min(u_min, half_u_[j]);
  level_.resize(n);
  int top = 0;
  for (std::size_t j = 0; j < n; ++j) {
    level_[j] = size_level(half_u_[j] / u_min);
    top = std::max(top, level_[j]);
  }
  const auto levels = n == 0 ? 0 : static_cast<std::size_t>(top) + 1;
  std::vector<std::vector<std::int32_t>> members(levels);
  for (std::size_t j = 0; j < n; ++j)
    members[static_cast<std::size_t>(level_[j])].push_back(static_cast<std::int32_t>(j));
  exact_.assign(levels, FrameGrid{});
  cumulative_.assign(levels, FrameGrid{});
  std::vector<std::int32_t> upto;
  double upto_u = 0.0, upto_v = 0.0;
  for (std::size_t l = 0; l < levels; ++l) {
    FrameGrid& e = exact_[l];
    for (const std::int32_t j : members[l]) {
      e.u_max = std::max(e.u_max, half_u_[static_cast<std::size_t>(j)]);
      e.v_max = std::max(e.v_max, half_v_[static_cast<std::size_t>(j)]);
    }
    upto_u = std::max(upto_u, e.u_max);
    upto_v = std::max(upto_v, e.v_max);
    upto.insert(upto.end(), members[l].begin(), members[l].end());
    if (members[l].empty()) continue;
    e.grid.build(u_, v_, members[l], e.u_max, e.v_max);
    FrameGrid& c = cumulative_[l];
    c.u_max = upto_u;
    c.v_max = upto_v;
    c.grid.build(u_, v_, upto, c.u_max, c.v_max);
  }
}

}  // namespace pdmesh::reference
