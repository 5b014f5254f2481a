// The plain double-precision C++ reference implementation of each simulation step
// (host/sim/step_backend.hpp). Each function is named after the OpenCL kernel that mirrors it.
#pragma once
#include <cmath>

#include <vector>

#include "sim/reference/metric_pair.hpp"
#include "sim/step_backend.hpp"

namespace pdmesh::reference {

// Step 1 (binning.cpp): multi-level hashed cell grids, O(N) with bounded work per node.
void build_neighbours(const SimParticles& p, double cutoff, NeighbourList& list, NeighbourFlags& flags);

// Brute-force O(N^2) neighbour list with the same criterion; the oracle for the tests.
void build_neighbours_brute_force(const SimParticles& p, double cutoff, NeighbourList& list, NeighbourFlags& flags);

// Metric mode: every node's factor of the pair metric (metric_pair.hpp's pair_factor), in node order.
std::vector<Sym2> pair_factors(const SimParticles& p);

// Step 1 in metric mode (binning_metric.cpp; the two functions above forward to these).
void build_neighbours_metric(const SimParticles& p, double cutoff, NeighbourList& list, NeighbourFlags& flags);
void build_neighbours_metric_brute_force(const SimParticles& p, double cutoff, NeighbourList& list,
                                         NeighbourFlags& flags);

// Steps 2 and 3 (forces.cpp).
void compute_forces(const SimParticles& p, const NeighbourList& list, const ForceParams& params, ForceResult& out);

// Steps 2 and 3 in metric mode (forces_metric.cpp; compute_forces forwards to it).
void compute_forces_metric(const SimParticles& p, const NeighbourList& list, const ForceParams& params,
                           ForceResult& out);

// Step 4 and the reductions (time_step.cpp).
void time_step_and_move(const SimParticles& p, const ForceResult& forces, double dt_gm2, MoveResult& out);
// Heavy-ball momentum on the moves of time_step_and_move (StepBackend::apply_momentum).
void apply_momentum(const SimParticles& p, const ForceResult& forces, double beta, double mix, MoveResult& moves,
                    MomentumState& carried);
// p turned towards the force F: p = (1 - mix) p + mix |p| F / |F| (Euclidean lengths); unchanged where
// p = 0 or F = 0 (kernels/time_step.cl, momentum_steer).
void momentum_steer(double& px, double& py, double mix, double fx, double fy);
// d = g + beta p (p steered first where mix > 0), back to g against the force, capped to r0 / 3: one
// node's rule (kernels/time_step.cl, momentum_move, has the same expressions in the same order, so that
// double results agree bit for bit).
void momentum_move(double gx, double gy, double px, double py, double beta, double mix, double fx, double fy, double r0,
                   double& dx, double& dy);
// Metric mode: the same rule with the cap |d|_M <= r0 / 3 in the node's metric M = [[m11, m12], [m12, m22]].
void momentum_move_metric(double gx, double gy, double px, double py, double beta, double mix, double fx, double fy,
                          double r0, double m11, double m12, double m22, double& dx, double& dy);
StepSums reduce(const SimParticles& p, const ForceResult& forces, const MoveResult& moves);

// The pair force of eq. 5.11 as a signed magnitude along +r_ij/r_ij (negative = repulsion),
// written as the kernels write it: 1/r^2 once, powers by multiplication.
inline double lj_pair_magnitude(double sigma, double inv_r2, double lj_a) {
  const double s2 = sigma * sigma * inv_r2;
  const double s6 = s2 * s2 * s2;
  return -4.0 * lj_a * sigma * (s6 * s6 - s6);
}

// |df/dr| and |f|/r of eq. 5.11 for the stability bound: the larger of the two is the norm of the
// pair's 2x2 force Jacobian (radial and transverse parts). Returns max(|df/dr|, |f|/r).
inline double lj_pair_stiffness(double sigma, double inv_r2, double inv_r, double lj_a) {
  const double s2 = sigma * sigma * inv_r2;
  const double s6 = s2 * s2 * s2;
  const double scale = 4.0 * lj_a * sigma * inv_r;
  const double radial = std::fabs(scale * (12.0 * s6 * s6 - 6.0 * s6));
  const double transverse = std::fabs(scale * (s6 * s6 - s6));
  return radial > transverse ? radial : transverse;
}

}  // namespace pdmesh::reference
