// Reference steps 2 and 3 in metric mode (SimParticles::m11, m12, m22; metric_pair.hpp): the pair
// force of eq. 5.11 with sigma = 1 in the pair's metric, and r0 as the pair's metric distance.
// In the metric coordinates xi = S^-1 x of a pair (S = M_ij^(-1/2), M_ij the geometric mean of the two
// metrics) the pair is isotropic with unit spacing: force g(rho) along the unit vector S^-1 d / rho. A
// move dxi maps back to S dxi, so the physical force is S g(rho) S^-1 d / rho = g(rho) d / rho: along
// d, with g = eq. 5.11 at sigma = 1. With M = I / q^2 this is the isotropic force with
// sigma = sqrt(q_i q_j), rho = r / sigma (eq. 5.11's (q_i + q_j) / 2 when q_i = q_j).
#include <algorithm>
#include <cmath>
#include <cstdint>

#include "core/parallel.hpp"
#include "sim/reference/metric_pair.hpp"
#include "sim/reference/reference_backend.hpp"

namespace pdmesh::reference {

// The fewest nodes worth a thread in the per-node loops below (parallel_for's min_chunk): a metric
// node's row costs microseconds, so runs of a few thousand nodes use every core.
constexpr std::size_t kMetricNodesPerThread = 256;

std::vector<Sym2> pair_factors(const SimParticles& p) {
  std::vector<Sym2> s(p.size());
  parallel_for(
      p.size(), [&](std::size_t i) { s[i] = pair_factor(p.m11[i], p.m12[i], p.m22[i]); }, 4 * kMetricNodesPerThread);
  return s;
}

void compute_forces_metric(const SimParticles& p, const NeighbourList& list, const ForceParams& params,
                           ForceResult& out) {
  const std::size_t n = p.size();
  const auto stride = static_cast<std::size_t>(list.stride);
  out.fx.assign(n, 0.0);
  out.fy.assign(n, 0.0);
  out.r0.assign(n, 0.0);
  out.coincident_pairs = 0;
  const bool stability = params.stability_factor > 0.0;
  if (stability)
    out.dt2_limit.assign(n, HUGE_VAL);
  else
    out.dt2_limit.clear();
  const std::vector<Sym2> s = pair_factors(p);
  // Each node's sums are its own (its row of the full list), so the threads change no bit; the
  // coincident pairs are counted per node and added in node order.
  std::vector<std::uint32_t> coincident(n, 0);
  parallel_for(
      n,
      [&](std::size_t i) {
        if (p.kind[i] == kSimFixed) return;
        const double xi = p.x[i], yi = p.y[i];
        const std::size_t base = i * stride;
        const std::size_t count = std::min(static_cast<std::size_t>(list.count[i]), stride);
        double fx = 0.0, fy = 0.0, stiffness = 0.0;
        for (std::size_t k = 0; k < count; ++k) {
          const auto j = static_cast<std::size_t>(list.index[base + k]);
          const double dx = p.x[j] - xi, dy = p.y[j] - yi;
          const double rho2 = pair_distance2(s[i], s[j], dx, dy);
          if (rho2 == 0.0) {
            ++coincident[i];
            continue;
          }
          const double inv_rho2 = 1.0 / rho2;
          const double inv_rho = std::sqrt(inv_rho2);
          const double f = lj_pair_magnitude(1.0, inv_rho2, params.lj_a) * inv_rho;
          fx += f * dx;
          fy += f * dy;
          // In the pair's metric coordinates the step is isotropic with sigma = 1; dt is the same there.
          if (stability) stiffness += lj_pair_stiffness(1.0, inv_rho2, inv_rho, params.lj_a);
        }
        if (stability && stiffness > 0.0) out.dt2_limit[i] = 2.0 * params.stability_factor / stiffness;
        if (p.kind[i] == kSimBoundary) {
          const double ft = fx * p.tx[i] + fy * p.ty[i];
          fx = ft * p.tx[i];
          fy = ft * p.ty[i];
        }
        out.fx[i] = fx;
        out.fy[i] = fy;
        const bool any_direction = params.r0_any_direction && (fx != 0.0 || fy != 0.0);
        double best2 = HUGE_VAL;
        for (std::size_t k = 0; k < count; ++k) {
          const auto j = static_cast<std::size_t>(list.index[base + k]);
          const double dx = p.x[j] - xi, dy = p.y[j] - yi;
          const double rho2 = pair_distance2(s[i], s[j], dx, dy);
          if (rho2 > 0.0 && rho2 < best2 && (any_direction || pair_metric_dot_sign(s[i], s[j], fx, fy, dx, dy) > 0.0))
            best2 = rho2;
        }
        out.r0[i] = best2 < HUGE_VAL ? std::sqrt(best2) : 0.0;
      },
      kMetricNodesPerThread);
  for (const std::uint32_t c : coincident) out.coincident_pairs += c;
}

}  // namespace pdmesh::reference
