// Stability of the explicit step dx = dt^2/2 F (thesis eqs. 5.6-5.9): a compressed node between
// two fixed neighbours oscillates with period 2 and growing amplitude once dt_GM^2 |df/dr| exceeds
// the forward-Euler limit; the optional stiffness bound (ForceParams::stability_factor) damps it.
#include <catch2/catch.hpp>

#include <cmath>
#include <vector>

#include "sim/reference/reference_backend.hpp"
#include "sim_fixtures.hpp"

using namespace pdmesh;

namespace {

using pdmesh_test::add;

// d/dr of the signed pair magnitude of eq. 5.11 (sigma = 1), closed form.
double lj_derivative(double r, double a) { return 4.0 * a * (12.0 * std::pow(r, -13) - 6.0 * std::pow(r, -7)); }

// Fixed nodes at x = -gap and +gap, q = 1, one interior node at (x0, 0); runs `iterations`
// iterations of lists, forces, time step and move at a constant dt_GM and returns the interior x.
std::vector<double> chain_positions(double gap, double x0, double dt_gm, double stability_factor, int iterations) {
  SimParticles p;
  add(p, -gap, 0.0, 1.0, kSimFixed);
  add(p, x0, 0.0, 1.0, kSimInterior);
  add(p, gap, 0.0, 1.0, kSimFixed);
  auto backend = make_reference_backend();
  NeighbourList list;
  NeighbourFlags flags;
  ForceResult forces;
  MoveResult moves;
  ForceParams params;
  params.stability_factor = stability_factor;
  std::vector<double> xs{x0};
  for (int it = 0; it < iterations; ++it) {
    build_neighbours_growing(*backend, p, params.cutoff, list, flags);
    backend->compute_forces(p, list, params, forces);
    backend->time_step_and_move(p, forces, dt_gm * dt_gm, moves);
    p.x[1] += moves.dx[1];
    p.y[1] += moves.dy[1];
    xs.push_back(p.x[1]);
  }
  return xs;
}

}  // namespace

TEST_CASE("thesis step: a compressed node between two fixed ones grows a period-2 oscillation", "[sim][stability]") {
  // r = 0.85 sigma: |df/dr| = 4a (12 r^-13 - 6 r^-7) = 4830 per bond, lambda = 2 |df/dr|.
  // dt_GM = 0.025 (the thesis' random-start value for circle_circle): h lambda = dt^2/2 lambda = 3.02,
  // so the linearised update x <- (1 - h lambda) x multiplies the offset by -2.02 every iteration.
  const double gap = 0.85, dt = 0.025, x0 = 1e-6;
  const double lambda = 2.0 * lj_derivative(gap, 15.0);
  const double factor = 1.0 - 0.5 * dt * dt * lambda;
  REQUIRE(factor < -2.0);
  const std::vector<double> xs = chain_positions(gap, x0, dt, 0.0, 12);
  // First step: the closed-form linear factor (the offset is 1e-6 sigma: linear within 1e-5).
  CHECK(xs[1] / xs[0] == Approx(factor).epsilon(1e-4));
  for (std::size_t k = 1; k < xs.size(); ++k) {
    INFO("iteration " << k << ": x = " << xs[k]);
    CHECK(xs[k] * xs[k - 1] < 0.0);                  // the sign alternates (period 2)
    CHECK(std::fabs(xs[k]) > std::fabs(xs[k - 1]));  // and the amplitude grows
  }
  CHECK(std::fabs(xs.back()) > 1e3 * x0);
}

TEST_CASE("stiffness bound: the same node settles in a few steps", "[sim][stability]") {
  const double gap = 0.85, dt = 0.025, x0 = 1e-6;
  for (const double c : {0.5, 1.0}) {
    const std::vector<double> xs = chain_positions(gap, x0, dt, c, 20);
    INFO("stability factor " << c);
    // dt_i^2 = 2c/K_i, K_i = 2 |df/dr| = lambda: the linear factor is 1 - c, in [0, 1).
    CHECK(std::fabs(xs[1]) <= (1.0 - c) * x0 + 1e-3 * x0);
    CHECK(std::fabs(xs.back()) < 1e-12);
  }
}

TEST_CASE("stiffness bound: lj_pair_stiffness is the norm of the pair force Jacobian", "[sim][stability]") {
  const double a = 15.0;
  for (const double sigma : {0.07, 1.0, 3.0}) {
    for (const double ratio : {0.5, 0.85, 1.0, 1.1, 1.2, 1.49}) {
      const double r = ratio * sigma;
      // Central difference of the signed magnitude (closed form, eq. 5.11) against the radial part,
      // f/r for the transverse part.
      const double h = 1e-6 * r;
      auto f = [&](double rr) { return reference::lj_pair_magnitude(sigma, 1.0 / (rr * rr), a); };
      const double radial = std::fabs((f(r + h) - f(r - h)) / (2.0 * h));
      const double transverse = std::fabs(f(r)) / r;
      INFO("sigma " << sigma << " r/sigma " << ratio);
      CHECK(reference::lj_pair_stiffness(sigma, 1.0 / (r * r), 1.0 / r, a) ==
            Approx(std::max(radial, transverse)).epsilon(1e-6));
    }
  }
}

TEST_CASE("stiffness bound: dt2_limit is empty when off and 2c/K_i when on, and the step takes the minimum",
          "[sim][stability]") {
  SimParticles p;
  add(p, 0.0, 0.0, 1.0, kSimInterior);
  add(p, 0.9, 0.0, 1.0, kSimInterior);
  add(p, 5.0, 5.0, 1.0, kSimInterior);  // alone: no neighbours, K = 0
  auto backend = make_reference_backend();
  NeighbourList list;
  NeighbourFlags flags;
  build_neighbours_growing(*backend, p, 1.5, list, flags);
  ForceResult off, on;
  backend->compute_forces(p, list, ForceParams{}, off);
  CHECK(off.dt2_limit.empty());
  ForceParams params;
  params.stability_factor = 0.7;
  backend->compute_forces(p, list, params, on);
  REQUIRE(on.dt2_limit.size() == 3);
  const double k = std::fabs(lj_derivative(0.9, 15.0));  // radial part dominates at 0.9 sigma
  CHECK(on.dt2_limit[0] == Approx(2.0 * 0.7 / k).epsilon(1e-12));
  CHECK(on.dt2_limit[1] == Approx(2.0 * 0.7 / k).epsilon(1e-12));
  CHECK(on.dt2_limit[2] == HUGE_VAL);
  // Forces and r0 are unchanged by the option.
  CHECK(on.fx == off.fx);
  CHECK(on.r0 == off.r0);
  MoveResult moves;
  // Node 0 is pushed away from node 1 into empty space: r0 = 0, so only dt_GM (large here) limits it.
  const double dt_gm2 = 1.0;
  REQUIRE(off.r0[0] == 0.0);
  backend->time_step_and_move(p, on, dt_gm2, moves);
  CHECK(moves.dt2[0] == on.dt2_limit[0]);
  CHECK(moves.dx[0] == Approx(0.5 * on.dt2_limit[0] * on.fx[0]).epsilon(1e-15));
  CHECK(moves.dt2[2] == dt_gm2);
  backend->time_step_and_move(p, off, dt_gm2, moves);
  CHECK(moves.dt2[0] == dt_gm2);
}
