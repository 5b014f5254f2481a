// Particles in a metric (SimParticles::m11, m12, m22; host/sim/reference/metric_pair.hpp): the pair
// metric is the geometric mean of the two metrics, the force is eq. 5.11 with sigma = sqrt(q_i q_j) for
// M = I / q^2, a run in a constant stretched metric is the affine
// image of the isotropic run, the neighbour search finds exactly the pairs within the metric cut-off
// for metrics of aspect 100, and the OpenCL backend (double) equals the reference bit for bit.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "core/errors.hpp"
#include "opencl/opencl_backend.hpp"
#include "spacing/metric.hpp"
#include "sim/reference/metric_pair.hpp"
#include "sim/reference/reference_backend.hpp"
#include "sim_fixtures.hpp"
#include "step_backend_inputs.hpp"

using namespace pdmesh;
using pdmesh_test::add;
using pdmesh_test::set_metric;
using pdmesh_test::set_sizes;
using pdmesh_test::uniform;

namespace {

std::vector<int> row(const NeighbourList& list, std::size_t i) {
  const auto s = static_cast<std::size_t>(list.stride);
  const auto n = std::min(static_cast<std::size_t>(list.count[i]), s);
  return {list.index.begin() + static_cast<std::ptrdiff_t>(i * s),
          list.index.begin() + static_cast<std::ptrdiff_t>(i * s + n)};
}

// Random interior nodes in [0, 1]^2 with spacing graded 10x (q from 0.02 to 0.2).
SimParticles graded(std::mt19937_64& rng, std::size_t n) {
  SimParticles p;
  for (std::size_t i = 0; i < n; ++i) {
    const double x = uniform(rng), y = uniform(rng);
    add(p, x, y, 0.02 + 0.18 * x);
  }
  return p;
}

}  // namespace

// 2x2 matrices [[a, b], [c, d]] for the geometric mean's definition below.
struct Mat2 {
  double a, b, c, d;
};
Mat2 mul(const Mat2& x, const Mat2& y) {
  return {x.a * y.a + x.b * y.c, x.a * y.b + x.b * y.d, x.c * y.a + x.d * y.c, x.c * y.b + x.d * y.d};
}
Mat2 sqrtm(const Mat2& m) {  // SPD m: (M + s I) / sqrt(tr M + 2 s), s = sqrt(det M)
  const double s = std::sqrt(m.a * m.d - m.b * m.c), t = std::sqrt(m.a + m.d + 2.0 * s);
  return {(m.a + s) / t, m.b / t, m.c / t, (m.d + s) / t};
}
Mat2 inv(const Mat2& m) {
  const double det = m.a * m.d - m.b * m.c;
  return {m.d / det, -m.b / det, -m.c / det, m.a / det};
}

TEST_CASE("the pair metric is the geometric mean of the two metrics", "[sim][metric]") {
  // A # B = A^1/2 (A^-1/2 B A^-1/2)^1/2 A^1/2, against the closed form of metric_pair.hpp, for random
  // metrics of aspect up to 1000 and sizes 1e-5 to 0.3 (the tanh layer's range).
  std::mt19937_64 rng(37);
  for (int k = 0; k < 2000; ++k) {
    SimParticles p;
    add(p, 0.0, 0.0, 1.0);
    add(p, 0.0, 0.0, 1.0);
    for (std::size_t i = 0; i < 2; ++i) {
      const double h1 = 1e-5 * std::pow(3e4, uniform(rng));
      const double h2 = h1 * std::pow(1000.0, uniform(rng) - 0.5);
      set_sizes(p, i, h1, h2, M_PI * uniform(rng));
    }
    const Mat2 a{p.m11[0], p.m12[0], p.m12[0], p.m22[0]}, b{p.m11[1], p.m12[1], p.m12[1], p.m22[1]};
    const Mat2 ah = sqrtm(a), aih = inv(ah);
    const Mat2 g = mul(mul(ah, sqrtm(mul(mul(aih, b), aih))), ah);
    const double dx = uniform(rng) - 0.5, dy = uniform(rng) - 0.5;
    const double expected = g.a * dx * dx + (g.b + g.c) * dx * dy + g.d * dy * dy;
    const reference::Sym2 si = reference::pair_factor(a.a, a.b, a.d), sj = reference::pair_factor(b.a, b.b, b.d);
    INFO("pair " << k);
    REQUIRE(reference::pair_distance2(si, sj, dx, dy) == Approx(expected).epsilon(1e-6));
    REQUIRE(reference::pair_distance2(sj, si, dx, dy) == reference::pair_distance2(si, sj, dx, dy));
  }
}

TEST_CASE("across a steep size change the pair distance is the geometric mean of the two metric lengths",
          "[sim][metric]") {
  // Sizes 1e-4 and 0.1 (the tanh layer's edge): rho^2 = L_i L_j, not dominated by the coarse node
  // (the mean of the size tensors measured rho = 2 |d| / (h_i + h_j), 0.02 here instead of 0.63).
  const double hi = 1e-4, hj = 0.1, d = 0.002;
  const reference::Sym2 si = reference::pair_factor(1.0 / (hi * hi), 0.0, 1.0 / (hi * hi));
  const reference::Sym2 sj = reference::pair_factor(1.0 / (hj * hj), 0.0, 1.0 / (hj * hj));
  REQUIRE(reference::pair_distance2(si, sj, d, 0.0) == Approx((d / hi) * (d / hj)).epsilon(1e-12));
  REQUIRE(reference::pair_distance2(si, sj, 0.6 * d, 0.8 * d) == Approx((d / hi) * (d / hj)).epsilon(1e-12));
}

TEST_CASE("with M = I / q^2 the metric force is eq. 5.11 with sigma = sqrt(q_i q_j)", "[sim][metric]") {
  std::mt19937_64 rng(37);
  SimParticles iso = graded(rng, 400);
  iso.kind[5] = kSimFixed;
  NeighbourList list;
  NeighbourFlags flags;
  list.stride = 128;
  reference::build_neighbours_brute_force(iso, 1.5, list, flags);
  REQUIRE(flags.overflow == 0);
  REQUIRE(flags.pairs_within > 1000);
  SimParticles met = iso;
  for (std::size_t i = 0; i < met.size(); ++i)
    set_metric(met, i, 1.0 / (met.q[i] * met.q[i]), 0.0, 1.0 / (met.q[i] * met.q[i]));
  for (const double stability : {0.0, 0.5}) {
    const ForceParams params{1.5, 15.0, false, stability};
    ForceResult b;
    reference::compute_forces(met, list, params, b);
    REQUIRE(b.dt2_limit.size() == (stability > 0.0 ? iso.size() : 0));
    for (std::size_t i = 0; i < iso.size(); ++i) {
      INFO("node " << i << " stability " << stability);
      double fx = 0.0, fy = 0.0, scale = 1e-300, stiffness = 0.0;
      if (iso.kind[i] != kSimFixed)
        for (int j : row(list, i)) {
          const auto uj = static_cast<std::size_t>(j);
          const double sigma = std::sqrt(iso.q[i] * iso.q[uj]);
          const double dx = iso.x[uj] - iso.x[i], dy = iso.y[uj] - iso.y[i];
          const double inv_rho2 = sigma * sigma / (dx * dx + dy * dy), inv_rho = std::sqrt(inv_rho2);
          const double f = reference::lj_pair_magnitude(1.0, inv_rho2, 15.0) * inv_rho;
          fx += f * dx;
          fy += f * dy;
          scale += std::fabs(f) * std::hypot(dx, dy);
          stiffness += reference::lj_pair_stiffness(1.0, inv_rho2, inv_rho, 15.0);
        }
      REQUIRE(std::fabs(b.fx[i] - fx) <= 1e-12 * scale + 1e-12);
      REQUIRE(std::fabs(b.fy[i] - fy) <= 1e-12 * scale + 1e-12);
      if (stability > 0.0 && stiffness > 0.0) REQUIRE(b.dt2_limit[i] == Approx(1.0 / stiffness).epsilon(1e-12));
    }
  }
}

TEST_CASE("with constant M = I / q^2 the time step and moves equal the isotropic ones", "[sim][metric]") {
  std::mt19937_64 rng(8);
  SimParticles iso;
  const double q = 0.05;
  for (int i = 0; i < 200; ++i) add(iso, uniform(rng), uniform(rng), q);
  NeighbourList list;
  NeighbourFlags flags;
  list.stride = 64;
  reference::build_neighbours(iso, 1.5, list, flags);
  SimParticles met = iso;
  for (std::size_t i = 0; i < met.size(); ++i) set_metric(met, i, 1.0 / (q * q), 0.0, 1.0 / (q * q));
  NeighbourList mlist;
  reference::build_neighbours(met, 1.5, mlist, flags);
  REQUIRE(mlist.count == list.count);
  ForceResult a, b;
  reference::compute_forces(iso, list, {}, a);
  reference::compute_forces(met, list, {}, b);
  MoveResult ma, mb;
  reference::time_step_and_move(iso, a, 1.0, ma);
  reference::time_step_and_move(met, b, 1.0, mb);
  for (std::size_t i = 0; i < iso.size(); ++i) {
    INFO("node " << i);
    REQUIRE(b.r0[i] * q == Approx(a.r0[i]).epsilon(1e-12));
    REQUIRE(mb.dt2[i] == Approx(ma.dt2[i]).epsilon(1e-12));
    REQUIRE(mb.dx[i] == Approx(ma.dx[i]).epsilon(1e-10).margin(1e-15));
    REQUIRE(mb.dy[i] == Approx(ma.dy[i]).epsilon(1e-10).margin(1e-15));
  }
}

TEST_CASE("a run in a constant stretched metric is the affine image of the isotropic run", "[sim][metric]") {
  // Unit spacing in the isotropic run; the metric run has its points scaled by (hx, hy) = (1, 0.01) and
  // M = diag(1/hx^2, 1/hy^2), rotated by 30 degrees in the second section.
  const double hx = 1.0, hy = 0.01;
  const double angle = GENERATE(0.0, 0.5235987755982988);
  const double c = std::cos(angle), s = std::sin(angle);
  auto map = [&](double u, double v, double& x, double& y) {
    const double a = hx * u, b = hy * v;
    x = c * a - s * b;
    y = s * a + c * b;
  };
  std::mt19937_64 rng(11);
  SimParticles iso;
  // A fixed ring around a perturbed lattice, slightly too dense, so the interior has to relax.
  for (int k = 0; k < 40; ++k) {
    const double t = 2.0 * M_PI * k / 40;
    add(iso, 6.0 * std::cos(t), 6.0 * std::sin(t), 1.0, kSimFixed);
  }
  for (int i = -5; i <= 5; ++i)
    for (int j = -5; j <= 5; ++j) {
      const double u = 0.9 * (i + 0.5 * (j & 1)) + 0.2 * (uniform(rng) - 0.5);
      const double v = 0.9 * 0.866 * j + 0.2 * (uniform(rng) - 0.5);
      if (u * u + v * v < 5.0 * 5.0) add(iso, u, v, 1.0);
    }
  SimParticles met = iso;
  for (std::size_t i = 0; i < met.size(); ++i) {
    map(iso.x[i], iso.y[i], met.x[i], met.y[i]);
    set_sizes(met, i, hx, hy, angle);
  }
  NeighbourList la, lb;
  NeighbourFlags fa, fb;
  std::size_t same_lists = 0;
  for (int step = 0; step < 40; ++step) {
    reference::build_neighbours(iso, 1.5, la, fa);
    reference::build_neighbours(met, 1.5, lb, fb);
    REQUIRE(fa.overflow == 0);
    // The lists agree but for pairs within rounding of the cut-off (rho = 1.5 exactly in the lattice);
    // both runs take the isotropic list, so such a pair cannot split them.
    if (lb.count == la.count && lb.index == la.index) ++same_lists;
    // The stable settings (stability bound, dt_GM = 0.03): an unstable step would amplify rounding.
    const ForceParams params{1.5, 15.0, false, 1.0};
    ForceResult a, b;
    reference::compute_forces(iso, la, params, a);
    reference::compute_forces(met, la, params, b);
    MoveResult ma, mb;
    reference::time_step_and_move(iso, a, 0.03 * 0.03, ma);
    reference::time_step_and_move(met, b, 0.03 * 0.03, mb);
    for (std::size_t i = 0; i < iso.size(); ++i) {
      iso.x[i] += ma.dx[i];
      iso.y[i] += ma.dy[i];
      met.x[i] += mb.dx[i];
      met.y[i] += mb.dy[i];
    }
  }
  double moved = 0.0;
  for (std::size_t i = 0; i < iso.size(); ++i) {
    double x, y;
    map(iso.x[i], iso.y[i], x, y);
    INFO("node " << i);
    // In metric units (the isotropic frame): the image agrees to 1e-9.
    const double ex = x - met.x[i], ey = y - met.y[i];
    const double eu = (c * ex + s * ey) / hx, ev = (-s * ex + c * ey) / hy;
    REQUIRE(std::hypot(eu, ev) < 1e-9);
    if (iso.kind[i] == kSimInterior) moved = std::max(moved, std::hypot(iso.x[i], iso.y[i]));
  }
  REQUIRE(moved > 0.0);
  REQUIRE(same_lists >= 30);
}

TEST_CASE("the metric neighbour search finds exactly the pairs within the metric cut-off at aspect 100",
          "[sim][metric][neighbours]") {
  std::mt19937_64 rng(100);
  SimParticles p;
  const std::size_t n = 1500;
  for (std::size_t i = 0; i < n; ++i) {
    const double x = uniform(rng), y = uniform(rng);
    // Some fixed and boundary kinds too: they are found, but have no (or only {prev, next}) rows.
    add(p, x, y, 1.0, i % 97 == 0 ? kSimFixed : kSimInterior);
  }
  SECTION("linear case, aspect up to 100") {
    for (std::size_t i = 0; i < n; ++i) set_sizes(p, i, 0.1, 0.001 + 0.198 * std::fabs(p.y[i] - 0.5), 0.0);
  }
  SECTION("random directions, aspect 100, sizes varying 10x") {
    for (std::size_t i = 0; i < n; ++i) {
      const double h = 0.05 + 0.45 * uniform(rng);
      set_sizes(p, i, h, h / 100.0, M_PI * uniform(rng));
    }
  }
  SECTION("isotropic bubbles of sizes 1000x apart") {
    for (std::size_t i = 0; i < n; ++i) {
      const double h = 0.0002 * std::pow(1000.0, uniform(rng));
      set_sizes(p, i, h, h, 0.0);
    }
  }
  bool layer = false;
  SECTION("a thin layer at slope 0.1, aspect 1000, among isotropic nodes and bubbles across it") {
    layer = true;
    // Most nodes in a band 0.01 wide along y = 0.1 x + 0.45 with sizes 0.2 along it and 0.0002 across
    // (the search's frame follows the layer), the rest isotropic (0.02 to 0.2) or stretched across
    // the layer (aspect 100 at 90 degrees to it), so that pairs of very different bubbles are found.
    const double along = std::atan(0.1);
    for (std::size_t i = 0; i < n; ++i) {
      if (i % 3 != 0) {
        p.y[i] = 0.45 + 0.1 * p.x[i] + 0.01 * (uniform(rng) - 0.5);
        set_sizes(p, i, 0.2, 0.0002, along);
      } else if (i % 9 == 0) {
        set_sizes(p, i, 0.1, 0.001, along + 0.5 * M_PI);
      } else {
        const double h = 0.02 + 0.18 * uniform(rng);
        set_sizes(p, i, h, h, 0.0);
      }
    }
  }
  NeighbourList brute, fast, cached;
  NeighbourFlags fb, ff, fc;
  brute.stride = fast.stride = 1024;
  reference::build_neighbours_brute_force(p, 1.5, brute, fb);
  reference::build_neighbours(p, 1.5, fast, ff);
  REQUIRE(fb.first_invalid == -1);
  REQUIRE(fb.overflow == 0);
  REQUIRE(fb.pairs_within > n);
  REQUIRE(fast.count == brute.count);
  // The layer's bubbles search strips along it: few candidates per pair found (the square of their long
  // axis would hold the layer's whole width).
  INFO("candidates " << ff.pairs_examined << " for " << ff.pairs_within << " pairs");
  if (layer) REQUIRE(ff.pairs_examined < 25 * ff.pairs_within);
  auto backend = make_reference_backend();
  build_neighbours_growing(*backend, p, 1.5, cached, fc);
  REQUIRE(fc.pairs_within == fb.pairs_within);
  const std::vector<reference::Sym2> s = reference::pair_factors(p);
  for (std::size_t i = 0; i < n; ++i) {
    INFO("node " << i);
    REQUIRE(row(fast, i) == row(brute, i));
    REQUIRE(row(cached, i) == row(brute, i));
    if (p.kind[i] != kSimInterior) continue;
    // The oracle itself: every listed pair within the cut-off, the relation symmetric among interior nodes.
    for (int j : row(brute, i)) {
      const auto uj = static_cast<std::size_t>(j);
      REQUIRE(reference::pair_distance2(s[i], s[uj], p.x[uj] - p.x[i], p.y[uj] - p.y[i]) <= 2.25);
      if (p.kind[uj] == kSimInterior) {
        const std::vector<int> back = row(brute, uj);
        REQUIRE(std::binary_search(back.begin(), back.end(), static_cast<int>(i)));
      }
    }
  }
}

TEST_CASE("a node with a metric that is not positive definite is reported by index", "[sim][metric]") {
  SimParticles p;
  for (int i = 0; i < 5; ++i) add(p, 0.1 * i, 0.0, 0.1);
  for (std::size_t i = 0; i < 5; ++i) set_sizes(p, i, 0.1, 0.01, 0.3);
  set_metric(p, 3, 1.0, 2.0, 1.0);  // det < 0
  NeighbourList list;
  NeighbourFlags flags;
  reference::build_neighbours(p, 1.5, list, flags);
  REQUIRE(flags.first_invalid == 3);
  set_metric(p, 3, 100.0, 0.0, 100.0);
  set_metric(p, 1, NAN, 0.0, 1.0);
  reference::build_neighbours(p, 1.5, list, flags);
  REQUIRE(flags.first_invalid == 1);
}

// One test body for both backends: a relaxation run in a varying metric of aspect up to 100 (the linear
// case's sizes, rotated by an angle varying with x), with the stability bound and momentum, driven by
// each backend's own outputs. Double on the device must equal the reference bit for bit.
namespace {

struct Trace {
  std::vector<double> x, y, fx, fy, r0, dt2, limit;
  std::vector<std::int32_t> count, index;
  std::vector<double> sums;
};

std::vector<Trace> metric_run(StepBackend& backend, SimParticles p, int steps, double mix = 0.0) {
  std::vector<Trace> out;
  NeighbourList list;
  NeighbourFlags flags;
  ForceResult forces;
  MoveResult moves;
  MomentumState carried;
  const ForceParams params{1.5, 15.0, false, 1.0};
  for (int step = 0; step < steps; ++step) {
    build_neighbours_growing(backend, p, 1.5, list, flags);
    backend.compute_forces(p, list, params, forces);
    backend.time_step_and_move(p, forces, 0.03 * 0.03, moves);
    backend.apply_momentum(p, forces, 0.9, mix, moves, carried);
    const StepSums sums = backend.reduce(p, forces, moves);
    for (std::size_t i = 0; i < p.size(); ++i) {
      p.x[i] += moves.dx[i];
      p.y[i] += moves.dy[i];
    }
    out.push_back({p.x,
                   p.y,
                   forces.fx,
                   forces.fy,
                   forces.r0,
                   moves.dt2,
                   forces.dt2_limit,
                   list.count,
                   list.index,
                   {static_cast<double>(sums.moving), sums.sum_force, sums.max_force, sums.sum_kinetic}});
  }
  return out;
}

SimParticles varying_metric_input() {
  std::mt19937_64 rng(2024);
  SimParticles p;
  for (int k = 0; k < 400; ++k) {
    const double x = uniform(rng), y = uniform(rng);
    add(p, x, y, 1.0, k < 20 ? kSimFixed : kSimInterior);
  }
  for (std::size_t i = 0; i < p.size(); ++i)
    set_sizes(p, i, 0.1, 0.001 + 0.198 * std::fabs(p.y[i] - 0.5), 0.5 * p.x[i]);
  return p;
}

}  // namespace

TEST_CASE("metric mode on the OpenCL backend in double equals the reference bit for bit", "[sim][metric][opencl]") {
  const SimParticles p = varying_metric_input();
  auto host = make_reference_backend();
  auto device = ocl::make_opencl_backend(pdmesh::test::test_context(), ocl::Precision::Double);
  // Without and with the carried moves steered towards the force (SimOptions::momentum_mix).
  const double mix = GENERATE(0.0, 0.2);
  INFO("momentum mix " << mix);
  const std::vector<Trace> a = metric_run(*host, p, 30, mix);
  const std::vector<Trace> b = metric_run(*device, p, 30, mix);
  REQUIRE(a.size() == b.size());
  double largest_move = 0.0;
  for (std::size_t step = 0; step < a.size(); ++step) {
    INFO("step " << step);
    REQUIRE(b[step].count == a[step].count);
    REQUIRE(b[step].index == a[step].index);
    REQUIRE(b[step].fx == a[step].fx);
    REQUIRE(b[step].fy == a[step].fy);
    REQUIRE(b[step].r0 == a[step].r0);
    REQUIRE(b[step].limit == a[step].limit);
    REQUIRE(b[step].dt2 == a[step].dt2);
    REQUIRE(b[step].sums == a[step].sums);
    REQUIRE(b[step].x == a[step].x);
    REQUIRE(b[step].y == a[step].y);
  }
  for (std::size_t i = 0; i < p.size(); ++i)
    largest_move = std::max(largest_move, std::hypot(a.back().x[i] - p.x[i], a.back().y[i] - p.y[i]));
  REQUIRE(largest_move > 1e-4);  // the run moved
}

TEST_CASE("metric mode on the OpenCL backend in float follows the reference", "[sim][metric][opencl]") {
  SimParticles p = varying_metric_input();
  pdmesh::test::round_to_float(p);
  for (auto* v : {&p.m11, &p.m12, &p.m22})
    for (double& e : *v) e = static_cast<double>(static_cast<float>(e));
  auto host = make_reference_backend();
  auto device = ocl::make_opencl_backend(pdmesh::test::test_context(), ocl::Precision::Float);
  NeighbourList list;
  NeighbourFlags flags;
  build_neighbours_growing(*host, p, 1.5, list, flags);
  ForceResult a, b;
  host->compute_forces(p, list, {1.5, 15.0, false, 1.0}, a);
  device->compute_forces(p, list, {1.5, 15.0, false, 1.0}, b);
  const std::vector<reference::Sym2> s = reference::pair_factors(p);
  for (std::size_t i = 0; i < p.size(); ++i) {
    INFO("node " << i);
    // Float rounding relative to the sum of the pair forces' magnitudes (the net force may cancel).
    double scale = 0.0;
    for (int j : row(list, i)) {
      const auto uj = static_cast<std::size_t>(j);
      const double dx = p.x[uj] - p.x[i], dy = p.y[uj] - p.y[i];
      const double rho2 = reference::pair_distance2(s[i], s[uj], dx, dy);
      scale += std::fabs(reference::lj_pair_magnitude(1.0, 1.0 / rho2, 15.0)) * std::hypot(dx, dy) / std::sqrt(rho2);
    }
    REQUIRE(std::hypot(b.fx[i] - a.fx[i], b.fy[i] - a.fy[i]) <= 1e-4 * scale);
    REQUIRE(b.r0[i] == Approx(a.r0[i]).epsilon(1e-4));
  }
}

TEST_CASE("nodes relaxed in the linear case's metric sit at unit metric length from their nearest neighbours",
          "[sim][metric]") {
  // UGAWG's linear metric on the unit square (h_x = 0.1, h_y = 0.001 + 0.198 |y - 0.5|, aspect up to
  // 100). Fixed boundary nodes at unit metric length (the sides' lengths in closed form: 10 along x,
  // ln(100) / 0.198 per half along y); the interior as many random nodes as a unit mesh holds, with density
  // sqrt(det M); 1500 iterations with the stability bound and momentum 0.9. Measured by the field's own
  // yardstick (spacing/metric.hpp edge_length, independent of the pair mean the force uses).
  auto metric_at = [](double y) {
    const double hy = 0.001 + 0.198 * std::fabs(y - 0.5);
    return Metric{100.0, 0.0, 1.0 / (hy * hy)};
  };
  SimParticles p;
  auto put = [&](double x, double y, std::uint8_t kind) {
    add(p, x, y, 0.1, kind);
    const Metric m = metric_at(y);
    set_metric(p, p.size() - 1, m.m11, m.m12, m.m22);
  };
  for (int k = 0; k < 10; ++k) {
    put(0.1 * k, 0.0, kSimFixed);
    put(1.0 - 0.1 * k, 1.0, kSimFixed);
  }
  // Along y: Y(y) = ln(1 + 0.198 |y - 0.5| / 0.001) / 0.198 is the metric length from y = 0.5; 23 pieces per half.
  const double half = std::log(100.0) / 0.198;
  for (int k = -23; k <= 23; ++k) {
    if (k == -23 || k == 23) continue;  // the corners are placed above
    const double t = half * std::fabs(k) / 23.0;
    const double y = 0.5 + std::copysign((std::exp(0.198 * t) - 1.0) * 0.001 / 0.198, k);
    put(0.0, y, kSimFixed);
    put(1.0, y, kSimFixed);
  }
  const std::size_t boundary = p.size();
  const double complexity = 2.0 * 10.0 * half;  // integral of sqrt(det M) = 10 / h_y over the square
  const auto interior = static_cast<std::size_t>(2.0 * complexity / std::sqrt(3.0) - boundary / 2.0 + 1.0);
  std::mt19937_64 rng(5);
  while (p.size() < boundary + interior) {
    const double x = uniform(rng), y = uniform(rng);
    if (uniform(rng) * 1000.0 <= 1.0 / (0.001 + 0.198 * std::fabs(y - 0.5))) put(x, y, kSimInterior);
  }
  auto backend = make_reference_backend();
  NeighbourList list;
  NeighbourFlags flags;
  ForceResult forces;
  MoveResult moves;
  MomentumState carried;
  const ForceParams params{1.5, 15.0, false, 1.0};
  for (int it = 0; it < 1500; ++it) {
    build_neighbours_growing(*backend, p, 1.5, list, flags);
    backend->compute_forces(p, list, params, forces);
    backend->time_step_and_move(p, forces, 0.03 * 0.03, moves);
    backend->apply_momentum(p, forces, 0.9, 0.0, moves, carried);
    for (std::size_t i = boundary; i < p.size(); ++i) {
      double x = p.x[i] + moves.dx[i], y = p.y[i] + moves.dy[i];
      if (x <= 0.0 || x >= 1.0) x = 0.5 * (p.x[i] + (x <= 0.0 ? 0.0 : 1.0));
      if (y <= 0.0 || y >= 1.0) y = 0.5 * (p.y[i] + (y <= 0.0 ? 0.0 : 1.0));
      p.x[i] = x;
      p.y[i] = y;
      const Metric m = metric_at(y);
      set_metric(p, i, m.m11, m.m12, m.m22);
    }
  }
  std::vector<double> nearest;
  for (std::size_t i = boundary; i < p.size(); ++i) {
    double best = HUGE_VAL;
    for (std::size_t j = 0; j < p.size(); ++j)
      if (j != i)
        best =
            std::min(best, edge_length(metric_at(p.y[i]), metric_at(p.y[j]), Vec2{p.x[j] - p.x[i], p.y[j] - p.y[i]}));
    nearest.push_back(best);
  }
  std::sort(nearest.begin(), nearest.end());
  INFO("nearest-neighbour metric lengths: min " << nearest.front() << ", median " << nearest[nearest.size() / 2]
                                                << ", max " << nearest.back());
  REQUIRE(nearest.size() > 400);
  REQUIRE(nearest[nearest.size() / 2] == Approx(1.0).margin(0.05));
  REQUIRE(nearest.front() > 0.8);
  REQUIRE(nearest.back() < 1.2);
}

TEST_CASE("metric mode in float keeps the time step of a crowded pair in a fine metric", "[sim][metric][opencl]") {
  // Sizes 1e-3 and a pair at metric distance 1e-2: |F| ~ 6e22, so F^T M F (~ 4e51) is far past float's range.
  SimParticles p;
  add(p, 0.5, 0.5, 1e-3);
  add(p, 0.5 + 1e-5, 0.5, 1e-3);
  add(p, 0.5 - 1e-3, 0.5, 1e-3);
  for (std::size_t i = 0; i < p.size(); ++i) set_sizes(p, i, 1e-3, 1e-3, 0.0);
  NeighbourList list;
  NeighbourFlags flags;
  reference::build_neighbours(p, 1.5, list, flags);
  ForceResult forces;
  reference::compute_forces(p, list, {}, forces);
  REQUIRE(std::hypot(forces.fx[0], forces.fy[0]) > 1e20);
  pdmesh::test::round_to_float(forces);
  auto device = ocl::make_opencl_backend(pdmesh::test::test_context(), ocl::Precision::Float);
  MoveResult oracle, got;
  reference::time_step_and_move(p, forces, 1.0, oracle);
  device->time_step_and_move(p, forces, 1.0, got);
  const StepSums o = reference::reduce(p, forces, oracle), g = device->reduce(p, forces, oracle);
  for (std::size_t i = 0; i < p.size(); ++i) {
    INFO("node " << i);
    REQUIRE(got.dt2[i] > 0.0);
    REQUIRE(got.dt2[i] == Approx(oracle.dt2[i]).epsilon(1e-5));
    REQUIRE(got.dx[i] == Approx(oracle.dx[i]).epsilon(1e-5));
  }
  REQUIRE(std::isfinite(g.sum_force));
  REQUIRE(g.sum_force == Approx(o.sum_force).epsilon(1e-5));
  // (The kinetic sum, dt_GM^2 |F|_M^2 / 8 for the node facing no neighbour, is past float's range itself.)
}
