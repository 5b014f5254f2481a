// Reference step 4: local time step (thesis eqs. 5.8, 5.9), displacement (eq. 5.6), the optional
// heavy-ball momentum on it, and the reductions the history and the global time step rule need.
#include <algorithm>
#include <cmath>

#include "sim/reference/metric_pair.hpp"
#include "sim/reference/reference_backend.hpp"

namespace pdmesh::reference {

void time_step_and_move(const SimParticles& p, const ForceResult& forces, double dt_gm2, MoveResult& out) {
  const std::size_t n = p.size();
  out.dx.assign(n, 0.0);
  out.dy.assign(n, 0.0);
  out.dt2.assign(n, 0.0);
  const bool metric = p.has_metric();
  for (std::size_t i = 0; i < n; ++i) {
    if (p.kind[i] == kSimFixed) continue;
    const double fx = forces.fx[i], fy = forces.fy[i];
    // Metric mode: r0 is a metric distance and |F| is measured in the node's metric, so the move
    // dt^2/2 F is at most r0/3 long in that metric (eq. 5.8 in metric units).
    const double f2 = metric ? metric_norm2(p.m11[i], p.m12[i], p.m22[i], fx, fy) : fx * fx + fy * fy;
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

void momentum_steer(double& px, double& py, double mix, double fx, double fy) {
  const double pl = std::sqrt(px * px + py * py);
  const double fl = std::sqrt(fx * fx + fy * fy);
  // No carried motion or no force: no direction to turn (or to turn towards).
  if (!(pl > 0.0) || !(fl > 0.0)) return;
  px = (1.0 - mix) * px + mix * pl * fx / fl;
  py = (1.0 - mix) * py + mix * pl * fy / fl;
}

void momentum_move(double gx, double gy, double px, double py, double beta, double mix, double fx, double fy, double r0,
                   double& dx, double& dy) {
  // The carried move turned towards today's force (mix > 0 only): motion across the force is damped
  // while the speed along it is kept.
  if (mix > 0.0) momentum_steer(px, py, mix, fx, fy);
  dx = gx + beta * px;
  dy = gy + beta * py;
  // Motion carried against today's force would push the node uphill: the plain step instead.
  if (dx * fx + dy * fy < 0.0) {
    dx = gx;
    dy = gy;
  }
  // The thesis' rule that a node moves at most a third of the way to its nearest neighbour in the
  // force direction (eq. 5.8 bounds g alone) holds for the total move.
  if (r0 > 0.0) {
    const double cap = r0 / 3.0;
    const double len = std::sqrt(dx * dx + dy * dy);
    if (len > cap) {
      const double s = cap / len;
      dx = dx * s;
      dy = dy * s;
    }
  }
}

void momentum_move_metric(double gx, double gy, double px, double py, double beta, double mix, double fx, double fy,
                          double r0, double m11, double m12, double m22, double& dx, double& dy) {
  if (mix > 0.0) momentum_steer(px, py, mix, fx, fy);
  dx = gx + beta * px;
  dy = gy + beta * py;
  if (dx * fx + dy * fy < 0.0) {
    dx = gx;
    dy = gy;
  }
  if (r0 > 0.0) {
    const double cap = r0 / 3.0;
    const double len = std::sqrt(metric_norm2(m11, m12, m22, dx, dy));
    if (len > cap) {
      const double s = cap / len;
      dx = dx * s;
      dy = dy * s;
    }
  }
}

void apply_momentum(const SimParticles& p, const ForceResult& forces, double beta, double mix, MoveResult& moves,
                    MomentumState& carried) {
  const std::size_t n = p.size();
  const bool metric = p.has_metric();
  carried.px.resize(n, 0.0);
  carried.py.resize(n, 0.0);
  for (std::size_t i = 0; i < n; ++i) {
    if (p.kind[i] == kSimFixed) {
      carried.px[i] = carried.py[i] = 0.0;  // time_step_and_move left d = 0
      continue;
    }
    double dx, dy;
    if (metric)
      momentum_move_metric(moves.dx[i], moves.dy[i], carried.px[i], carried.py[i], beta, mix, forces.fx[i],
                           forces.fy[i], forces.r0[i], p.m11[i], p.m12[i], p.m22[i], dx, dy);
    else
      momentum_move(moves.dx[i], moves.dy[i], carried.px[i], carried.py[i], beta, mix, forces.fx[i], forces.fy[i],
                    forces.r0[i], dx, dy);
    moves.dx[i] = carried.px[i] = dx;
    moves.dy[i] = carried.py[i] = dy;
  }
}

StepSums reduce(const SimParticles& p, const ForceResult& forces, const MoveResult& moves) {
  StepSums s;
  const bool metric = p.has_metric();
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (p.kind[i] == kSimFixed) continue;
    const double f2 = metric ? metric_norm2(p.m11[i], p.m12[i], p.m22[i], forces.fx[i], forces.fy[i])
                             : forces.fx[i] * forces.fx[i] + forces.fy[i] * forces.fy[i];
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
