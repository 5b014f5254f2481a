// Tests of the simulation steps behind StepBackend (reference backend): neighbour lists against
// brute force, the pair force against its closed form, r0, the time step, and the reductions.
#include <catch2/catch.hpp>

#include <cmath>
#include <random>

#include "sim/reference/reference_backend.hpp"
#include "sim_fixtures.hpp"

using namespace pdmesh;

namespace {

using pdmesh_test::add;

double norm2_of(double x, double y) { return x * x + y * y; }

using pdmesh_test::uniform;

// Closed form of eq. 5.11 along +x for node 0 at the origin and node 1 at (r, 0).
double closed_form_fx(double q0, double q1, double r, double a) {
  const double s = 0.5 * (q0 + q1);
  return -4.0 * a * s * (std::pow(s / r, 12) - std::pow(s / r, 6));
}

ForceResult forces_of(const SimParticles& p, double cutoff = 1.5, double a = 15.0, bool r0_any = false) {
  auto backend = make_reference_backend();
  NeighbourList list;
  NeighbourFlags flags;
  build_neighbours_growing(*backend, p, cutoff, list, flags);
  ForceResult f;
  backend->compute_forces(p, list, {cutoff, a, r0_any}, f);
  return f;
}

// The neighbour sets of both builders must agree exactly (lists are sorted by index).
void require_same_lists(const SimParticles& p, double cutoff) {
  NeighbourList grid, brute;
  grid.stride = brute.stride = 8;
  NeighbourFlags gf, bf;
  auto backend = make_reference_backend();
  build_neighbours_growing(*backend, p, cutoff, grid, gf);
  reference::build_neighbours_brute_force(p, cutoff, brute, bf);
  if (bf.overflow) {
    brute.stride = grid.stride;
    reference::build_neighbours_brute_force(p, cutoff, brute, bf);
  }
  REQUIRE(grid.count == brute.count);
  REQUIRE(gf.pairs_within == bf.pairs_within);
  REQUIRE(gf.max_count == bf.max_count);
  for (std::size_t i = 0; i < p.size(); ++i) {
    for (int k = 0; k < grid.count[i]; ++k) {
      INFO("node " << i << " entry " << k);
      REQUIRE(grid.index[i * static_cast<std::size_t>(grid.stride) + static_cast<std::size_t>(k)] ==
              brute.index[i * static_cast<std::size_t>(brute.stride) + static_cast<std::size_t>(k)]);
    }
  }
}

}  // namespace

TEST_CASE("pair force: repulsion inside sigma, attraction outside, zero at sigma", "[sim]") {
  for (double r : {0.5, 0.9, 0.99, 1.0, 1.01, 1.2, 1.49}) {
    SimParticles p;
    add(p, 0.0, 0.0, 1.0);
    add(p, r, 0.0, 1.0);
    const auto f = forces_of(p);
    INFO("r = " << r);
    CHECK(f.fy[0] == 0.0);
    CHECK(f.fx[0] == Approx(closed_form_fx(1.0, 1.0, r, 15.0)).epsilon(1e-12));
    CHECK(f.fx[1] == -f.fx[0]);
    if (r < 1.0) CHECK(f.fx[0] < 0.0);  // pushed away from node 1
    if (r > 1.0) CHECK(f.fx[0] > 0.0);  // pulled towards node 1
    if (r == 1.0) CHECK(f.fx[0] == 0.0);
  }
}

TEST_CASE("pair force scales with sigma and uses the mean spacing", "[sim]") {
  for (double ratio : {0.8, 0.95, 1.3}) {
    SimParticles p1, p2;
    add(p1, 0.0, 0.0, 1.0);
    add(p1, ratio, 0.0, 1.0);
    add(p2, 0.0, 0.0, 2.0);
    add(p2, 2.0 * ratio, 0.0, 2.0);
    CHECK(forces_of(p2).fx[0] == Approx(2.0 * forces_of(p1).fx[0]).epsilon(1e-12));
  }
  // sigma_ij = (q_i + q_j) / 2, and node 1 (q = 1.4) sees node 0 within 1.5 * 1.4.
  SimParticles p;
  add(p, 0.0, 0.0, 0.6);
  add(p, 1.1, 0.0, 1.4);
  const auto f = forces_of(p);
  CHECK(f.fx[1] == Approx(-closed_form_fx(0.6, 1.4, 1.1, 15.0)).epsilon(1e-12));
  CHECK(f.fx[0] == 0.0);  // 1.1 > 1.5 * 0.6: node 1 is outside node 0's cut-off
  // lj_a scales linearly.
  CHECK(forces_of(p, 1.5, 30.0).fx[1] == Approx(2.0 * f.fx[1]).epsilon(1e-12));
}

TEST_CASE("r0 is the nearest neighbour in the force direction", "[sim]") {
  SimParticles p;
  add(p, 0.0, 0.0, 1.0);
  add(p, -0.7, 0.0, 1.0);  // nearest, repels towards +x, but lies behind the force
  add(p, 1.2, 0.0, 1.0);   // attracts towards +x: the only neighbour in front
  add(p, 0.0, 1.1, 1.0);   // perpendicular: F . r = 0 does not count
  add(p, 0.0, -1.1, 1.0);
  const auto f = forces_of(p);
  REQUIRE(f.fx[0] > 0.0);
  REQUIRE(f.fy[0] == 0.0);
  CHECK(f.r0[0] == 1.2);
  // The alternative rule takes the nearest neighbour in any direction.
  CHECK(forces_of(p, 1.5, 15.0, true).r0[0] == 0.7);
  // A node whose force points to empty space has no r0.
  SimParticles two;
  add(two, 0.0, 0.0, 1.0);
  add(two, 0.9, 0.0, 1.0);
  const auto g = forces_of(two);
  CHECK(g.fx[0] < 0.0);
  CHECK(g.r0[0] == 0.0);
  CHECK(g.r0[1] == 0.0);
  CHECK(forces_of(two, 1.5, 15.0, true).r0[1] == 0.9);
}

TEST_CASE("boundary nodes feel only their curve neighbours, projected on the tangent", "[sim]") {
  SimParticles p;
  add(p, 0.0, 0.0, 1.0, kSimFixed);
  add(p, 0.8, 0.0, 1.0, kSimBoundary);
  add(p, 2.0, 0.0, 1.0, kSimFixed);
  add(p, 0.8, 0.5, 1.0);  // interior node right above: ignored by the boundary node
  p.prev[1] = 0;
  p.next[1] = 2;
  p.tx[1] = 1.0;
  const auto f = forces_of(p);
  CHECK(f.fx[0] == 0.0);
  CHECK(f.fy[0] == 0.0);
  CHECK(f.fx[2] == 0.0);
  const double expected = -closed_form_fx(1.0, 1.0, 0.8, 15.0) + closed_form_fx(1.0, 1.0, 1.2, 15.0);
  REQUIRE(expected > 0.0);
  CHECK(f.fx[1] == Approx(expected).epsilon(1e-12));
  CHECK(f.fy[1] == 0.0);
  CHECK(f.r0[1] == Approx(1.2).epsilon(1e-15));
  // A tilted tangent keeps only the tangential component.
  p.tx[1] = std::sqrt(0.5);
  p.ty[1] = std::sqrt(0.5);
  const auto g = forces_of(p);
  CHECK(g.fx[1] == Approx(0.5 * expected).epsilon(1e-12));
  CHECK(g.fy[1] == Approx(0.5 * expected).epsilon(1e-12));
  // The interior node feels the boundary node and the fixed nodes within its cut-off.
  CHECK(g.fy[3] > 0.0);
}

TEST_CASE("time step: dt^2 = min(2 r0 / (3|F|), dt_GM^2) and dx = dt^2 / 2 F", "[sim]") {
  SimParticles p;
  for (int i = 0; i < 5; ++i) add(p, 0.0, 0.0, 1.0);
  p.kind[4] = kSimFixed;
  ForceResult f;
  f.fx = {3.0, 0.0, 30000.0, 2.0, 5.0};
  f.fy = {4.0, 0.0, 40000.0, 0.0, 5.0};
  f.r0 = {1.5, 1.0, 1.5, 0.0, 1.0};
  MoveResult m;
  const double dt_gm2 = 0.01 * 0.01;
  reference::time_step_and_move(p, f, dt_gm2, m);
  // |F| = 5: 2 * 1.5 / 15 = 0.2 > dt_GM^2, the global maximum wins.
  CHECK(m.dt2[0] == dt_gm2);
  CHECK(m.dx[0] == 0.5 * dt_gm2 * 3.0);
  CHECK(m.dy[0] == 0.5 * dt_gm2 * 4.0);
  // F = 0: no move.
  CHECK(m.dx[1] == 0.0);
  CHECK(m.dy[1] == 0.0);
  // |F| = 50000: the local step limits the move to r0 / 3.
  CHECK(m.dt2[2] == 2.0 * 1.5 / (3.0 * 50000.0));
  CHECK(std::hypot(m.dx[2], m.dy[2]) == Approx(0.5).epsilon(1e-14));
  // No neighbour in the force direction: the global maximum.
  CHECK(m.dt2[3] == dt_gm2);
  CHECK(m.dx[3] == 0.5 * dt_gm2 * 2.0);
  // Fixed nodes never move.
  CHECK(m.dx[4] == 0.0);
  CHECK(m.dy[4] == 0.0);

  const StepSums s = reference::reduce(p, f, m);
  CHECK(s.moving == 4);
  CHECK(s.max_force == 50000.0);
  CHECK(s.sum_force == 5.0 + 0.0 + 50000.0 + 2.0);
  const double ke = 0.5 * (norm2_of(m.dx[0], m.dy[0]) / m.dt2[0] + norm2_of(m.dx[2], m.dy[2]) / m.dt2[2] +
                           norm2_of(m.dx[3], m.dy[3]) / m.dt2[3]);
  CHECK(s.sum_kinetic == Approx(ke).epsilon(1e-14));
}

TEST_CASE("neighbour lists equal brute force: random uniform input", "[sim]") {
  std::mt19937_64 rng(42);
  for (std::size_t n : {0u, 1u, 2u, 7u, 93u, 997u}) {
    SimParticles p;
    for (std::size_t i = 0; i < n; ++i) add(p, 10.0 * uniform(rng), 10.0 * uniform(rng), 0.3 + 0.4 * uniform(rng));
    // Coincident nodes, and nodes exactly on cell edges of every level.
    if (n > 5) {
      add(p, p.x[3], p.y[3], p.q[3]);
      add(p, p.x[3], p.y[3], 0.7);
      add(p, 0.0, 0.0, 0.3);
      add(p, 0.9, 0.45, 0.3);
      add(p, 1.8, 0.9, 0.6);
      p.kind[2] = kSimFixed;
    }
    INFO("n = " << n);
    require_same_lists(p, 1.5);
  }
}

TEST_CASE("neighbour lists equal brute force: spacing graded 1000x, bounded work", "[sim]") {
  std::mt19937_64 rng(7);
  SimParticles p = pdmesh_test::graded_rings(rng);
  add(p, p.x[100], p.y[100], p.q[100]);  // coincident pair
  double q_min = HUGE_VAL, q_max = 0;
  for (double q : p.q) q_min = std::min(q_min, q), q_max = std::max(q_max, q);
  REQUIRE(q_max / q_min > 900.0);
  for (double cutoff : {1.5, 3.0}) require_same_lists(p, cutoff);

  NeighbourList list;
  NeighbourFlags flags;
  auto backend = make_reference_backend();
  build_neighbours_growing(*backend, p, 1.5, list, flags);
  // A single uniform grid would examine O(N) candidates per fine node here; the levelled grids
  // examine a bounded multiple of the pairs actually within the cut-off.
  INFO("examined " << flags.pairs_examined << " within " << flags.pairs_within);
  CHECK(flags.pairs_examined <= 6 * flags.pairs_within);
}

TEST_CASE("neighbour build reports invalid nodes and overflow", "[sim]") {
  SimParticles p;
  for (int i = 0; i < 20; ++i) add(p, 0.01 * i, 0.0, 1.0);
  NeighbourList list;
  list.stride = 4;
  NeighbourFlags flags;
  reference::build_neighbours(p, 1.5, list, flags);
  CHECK(flags.overflow == 1);
  CHECK(flags.max_count == 19);
  CHECK(list.count[0] == 19);
  auto backend = make_reference_backend();
  build_neighbours_growing(*backend, p, 1.5, list, flags);
  CHECK(flags.overflow == 0);
  CHECK(list.stride == 24);
  p.q[5] = 0.0;
  p.x[9] = NAN;
  reference::build_neighbours(p, 1.5, list, flags);
  CHECK(flags.first_invalid == 5);
}

// Heavy-ball momentum (reference::apply_momentum, docs/simulation.md "Momentum"), one node per rule.
TEST_CASE("momentum: d = g + beta p and the plain step against the force and |d| capped to r0 / 3", "[sim][momentum]") {
  SimParticles p;
  for (int i = 0; i < 6; ++i) add(p, 0.0, 0.0, 1.0);
  p.kind[5] = kSimFixed;
  ForceResult f;
  f.fx = {1.0, 1.0, 1.0, 1.0, 0.0, 1.0};
  f.fy = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0};
  f.r0 = {1.0, 1.0, 0.6, 0.0, 0.0, 1.0};
  MoveResult m;
  m.dx = {0.01, 0.01, 0.1, 0.1, 0.0, 0.0};
  m.dy = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0};
  MomentumState carried;
  carried.px = {0.02, -0.1, 0.5, 1.0, 0.25, 0.3};
  carried.py = {0.01, 0.0, 0.0, 0.0, -0.5, 0.3};
  reference::apply_momentum(p, f, 0.5, 0.0, m, carried);
  // Node 0: the accumulation, exactly the expression of the rule.
  CHECK(m.dx[0] == 0.01 + 0.5 * 0.02);
  CHECK(m.dy[0] == 0.0 + 0.5 * 0.01);
  // Node 1: 0.01 - 0.05 points against F: the plain step.
  CHECK(m.dx[1] == 0.01);
  CHECK(m.dy[1] == 0.0);
  // Node 2: 0.1 + 0.25 = 0.35 > r0 / 3 = 0.2: scaled to length 0.2, direction kept.
  CHECK(m.dx[2] == Approx(0.2).epsilon(1e-15));
  CHECK(m.dy[2] == 0.0);
  // Node 3: r0 = 0 (no neighbour in the force direction): no cap, 0.1 + 0.5.
  CHECK(m.dx[3] == 0.1 + 0.5 * 1.0);
  // Node 4: no force (g = 0): the carried motion goes on (d . F = 0 is not against it).
  CHECK(m.dx[4] == 0.5 * 0.25);
  CHECK(m.dy[4] == 0.5 * -0.5);
  // Node 5: fixed: no move, nothing carried.
  CHECK(m.dx[5] == 0.0);
  CHECK(m.dy[5] == 0.0);
  CHECK(carried.px[5] == 0.0);
  CHECK(carried.py[5] == 0.0);
  // p = d for every other node.
  for (std::size_t i = 0; i < 5; ++i) {
    CHECK(carried.px[i] == m.dx[i]);
    CHECK(carried.py[i] == m.dy[i]);
  }
}

TEST_CASE("momentum: a constant step accumulates to g (1 - beta^k) / (1 - beta) and beta 0 is the plain step",
          "[sim][momentum]") {
  SimParticles p;
  add(p, 0.0, 0.0, 1.0);
  ForceResult f;
  f.fx = {2.0};
  f.fy = {1.0};
  f.r0 = {10.0};
  MomentumState carried;  // empty: zero for the first iteration
  const double beta = 0.9, gx = 0.002, gy = 0.001;
  for (int k = 1; k <= 20; ++k) {
    MoveResult m;
    m.dx = {gx};
    m.dy = {gy};
    reference::apply_momentum(p, f, beta, 0.0, m, carried);
    const double sum = (1.0 - std::pow(beta, k)) / (1.0 - beta);
    INFO("iteration " << k);
    CHECK(m.dx[0] == Approx(gx * sum).epsilon(1e-13));
    CHECK(m.dy[0] == Approx(gy * sum).epsilon(1e-13));
    if (k == 1) CHECK(m.dx[0] == gx);  // p = 0 at the start: exactly g
  }
  // beta = 0 leaves the moves of time_step_and_move as they are, whatever is carried, where |g| is
  // clearly below r0 / 3 (where eq. 5.8 binds, |g| = r0 / 3 up to rounding, and the cap may round it:
  // the driver does not call apply_momentum for beta = 0, so SimOptions::momentum = 0 is the thesis' move).
  SimParticles q;
  for (int i = 0; i < 4; ++i) add(q, 0.0, 0.0, 1.0);
  ForceResult g;
  g.fx = {3.0, 0.0, 300.0, 2.0};
  g.fy = {4.0, 0.0, 400.0, 0.0};
  g.r0 = {1.5, 1.0, 1.5, 0.0};
  MoveResult plain, with_zero;
  reference::time_step_and_move(q, g, 1e-4, plain);
  with_zero = plain;
  MomentumState some;
  some.px = {0.3, -0.2, 0.1, 7.0};
  some.py = {-0.3, 0.2, 0.1, 7.0};
  reference::apply_momentum(q, g, 0.0, 0.0, with_zero, some);
  CHECK(with_zero.dx == plain.dx);
  CHECK(with_zero.dy == plain.dy);
}
