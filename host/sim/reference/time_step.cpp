// Reference step 4: local time step (thesis eqs. 5.8, 5.9), displacement (eq. 5.6), and the
// reductions the history and the global time step rule need.
#include <algorithm>
#include <cmath>

#include "sim/reference/reference_backend.hpp"

namespace pdmesh::reference {

void time_step_and_move(const SimParticles& p, const ForceResult& forces, double dt_gm2, MoveResult& out) {
  const std::size_t n = p.size();
  out.dx.assign(n, 0.0);
  out.dy.assign(n, 0.0);
  out.dt2.assign(n, 0.0);
  for (std::size_t i = 0; i < n; ++i) {
    if (p.kind[i] == kSimFixed) continue;
    const double fx = forces.fx[i], fy = forces.fy[i];
    const double f2 = fx * fx + fy * fy;
    // No force: no direction, no move; the step is the global maximum (r0 is undefined).
    // No neighbour in the force direction (r0 = 0): nothing limits the step but the global maximum.
    double dt2 = dt_gm2;
    if (f2 > 0.0 && forces.r0[i] > 0.0) dt2 = std::min(2.0 * forces.r0[i] / (3.0 * std::sqrt(f2)), dt_gm2);
    // Optional stability bound (ForceParams::stability_factor): keeps stiff (compressed) clusters
    // from the period-2 oscillation that a too large dt_GM starts.
    if (!forces.dt2_limit.empty()) dt2 = std::min(dt2, forces.dt2_limit[i]);
    out.dt2[i] = dt2;
    out.dx[i] = 0.5 * dt2 * fx;
    out.dy[i] = 0.5 * dt2 * fy;
  }
}

StepSums reduce(const SimParticles& p, const ForceResult& forces, const MoveResult& moves) {
  StepSums s;
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (p.kind[i] == kSimFixed) continue;
    const double f2 = forces.fx[i] * forces.fx[i] + forces.fy[i] * forces.fy[i];
    const double f = std::sqrt(f2);
    ++s.moving;
    s.sum_force += f;
    s.max_force = std::max(s.max_force, f);
    // 1/2 |dx/dt|^2 with dx = dt^2/2 F: the mean velocity over the step, so dt^2 |F|^2 / 8.
    s.sum_kinetic += 0.125 * moves.dt2[i] * f2;
  }
  return s;
}

}  // namespace pdmesh::reference
