// Reference steps 2 and 3: net Lennard-Jones-potential forces (thesis eq. 5.11) over the neighbour
// list, the tangential projection for boundary nodes, and r0 (eq. 5.3), gathered per node.
#include <algorithm>
#include <cmath>

#include "sim/reference/reference_backend.hpp"
#include "core/interrupt.hpp"

namespace pdmesh::reference {

void compute_forces(const SimParticles& p, const NeighbourList& list, const ForceParams& params, ForceResult& out) {
  if (p.has_metric()) {
    compute_forces_metric(p, list, params, out);
    return;
  }
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
  for (std::size_t i = 0; i < n; ++i) {
    if ((i & 16383) == 0) check_interrupt();  // only outputs written so far: the caller drops them
    if (p.kind[i] == kSimFixed) continue;
    const double xi = p.x[i], yi = p.y[i], qi = p.q[i];
    const std::size_t base = i * stride;
    const std::size_t count = std::min(static_cast<std::size_t>(list.count[i]), stride);
    double fx = 0.0, fy = 0.0, stiffness = 0.0;
    for (std::size_t k = 0; k < count; ++k) {
      const auto j = static_cast<std::size_t>(list.index[base + k]);
      const double dx = p.x[j] - xi, dy = p.y[j] - yi;
      const double r2 = dx * dx + dy * dy;
      // Coincident nodes give no direction; they are skipped and counted (the pair is reported).
      if (r2 == 0.0) {
        ++out.coincident_pairs;
        continue;
      }
      const double inv_r2 = 1.0 / r2;
      const double inv_r = std::sqrt(inv_r2);
      const double f = lj_pair_magnitude(0.5 * (qi + p.q[j]), inv_r2, params.lj_a) * inv_r;
      fx += f * dx;
      fy += f * dy;
      if (stability) stiffness += lj_pair_stiffness(0.5 * (qi + p.q[j]), inv_r2, inv_r, params.lj_a);
    }
    if (stability && stiffness > 0.0) out.dt2_limit[i] = 2.0 * params.stability_factor / stiffness;
    if (p.kind[i] == kSimBoundary) {
      // Boundary nodes slide along their curve: keep the tangential component only.
      const double ft = fx * p.tx[i] + fy * p.ty[i];
      fx = ft * p.tx[i];
      fy = ft * p.ty[i];
    }
    out.fx[i] = fx;
    out.fy[i] = fy;
    // r0: nearest neighbour strictly in the half-plane the force points into (0 = none), or with
    // r0_any_direction the nearest neighbour at all (see docs/simulation.md, "r0 rule").
    const bool any_direction = params.r0_any_direction && (fx != 0.0 || fy != 0.0);
    double best2 = HUGE_VAL;
    for (std::size_t k = 0; k < count; ++k) {
      const auto j = static_cast<std::size_t>(list.index[base + k]);
      const double dx = p.x[j] - xi, dy = p.y[j] - yi;
      const double r2 = dx * dx + dy * dy;
      if (r2 > 0.0 && (any_direction || fx * dx + fy * dy > 0.0) && r2 < best2) best2 = r2;
    }
    out.r0[i] = best2 < HUGE_VAL ? std::sqrt(best2) : 0.0;
  }
}

}  // namespace pdmesh::reference
