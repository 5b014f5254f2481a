// The Verlet candidate cache of the reference backend (neighbour_cache.hpp) against the exact
// multi-level build (reference::build_neighbours): identical lists and flags at every step of
// random, graded (1000x) and moving inputs, with positions, spacings, kinds and counts changing.
#include <catch2/catch.hpp>

#include <cmath>
#include <random>

#include "sim/reference/neighbour_cache.hpp"
#include "sim/reference/reference_backend.hpp"
#include "neighbour_list_checks.hpp"
#include "sim_fixtures.hpp"

using namespace pdmesh;

namespace {

using pdmesh_test::uniform;

using pdmesh_test::add;

void require_same(const SimParticles& p, double cutoff, reference::NeighbourCache& cache, int stride) {
  pdmesh_test::require_same_lists(p, cutoff, cache, stride, reference::build_neighbours);
}

// Moves every node by a random step of up to `step` times its spacing (some nodes 10x more) and
// lets its spacing drift by up to `drift` (relative); occasionally a node jumps far.
void jiggle(SimParticles& p, std::mt19937_64& rng, double step, double drift) {
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (p.kind[i] == kSimFixed) continue;
    const double s = step * p.q[i] * (rng() % 10 == 0 ? 10.0 : 1.0);
    p.x[i] += s * (2.0 * uniform(rng) - 1.0);
    p.y[i] += s * (2.0 * uniform(rng) - 1.0);
    p.q[i] *= 1.0 + drift * (2.0 * uniform(rng) - 1.0);
  }
  if (rng() % 7 == 0 && p.size() > 3) {
    const std::size_t i = rng() % p.size();
    p.x[i] = p.x[(i + 1) % p.size()];  // onto another node: coincident pair
    p.y[i] = p.y[(i + 1) % p.size()];
  }
}

SimParticles random_uniform(std::mt19937_64& rng, std::size_t n) {
  SimParticles p;
  for (std::size_t i = 0; i < n; ++i) add(p, 10.0 * uniform(rng), 10.0 * uniform(rng), 0.3 + 0.4 * uniform(rng));
  if (n > 2) p.kind[1] = kSimFixed;
  return p;
}

SimParticles graded(std::mt19937_64& rng) { return pdmesh_test::graded_rings(rng); }

}  // namespace

TEST_CASE("neighbour cache equals the exact build: random uniform input moving over 200 steps", "[sim][perf]") {
  for (double skin : {0.02, 0.2, 1.0}) {
    for (std::size_t n : {0u, 1u, 2u, 93u, 997u}) {
      std::mt19937_64 rng(42 + n);
      SimParticles p = random_uniform(rng, n);
      reference::NeighbourCache cache(skin, 0.1);
      for (int step = 0; step < 200; ++step) {
        INFO("skin " << skin << " n " << n << " step " << step);
        require_same(p, 1.5, cache, 8);
        jiggle(p, rng, 0.01, 0.01);
      }
      // The cache must actually be reused (else this test would not test it), but not forever.
      if (n > 2 && skin >= 0.2) CHECK(cache.rebuilds() < 100);
      if (n > 2) CHECK(cache.rebuilds() > 1);
    }
  }
}

TEST_CASE("neighbour cache equals the exact build: spacing graded 1000x, moving", "[sim][perf]") {
  std::mt19937_64 rng(7);
  SimParticles p = graded(rng);
  double q_min = HUGE_VAL, q_max = 0;
  for (double q : p.q) q_min = std::min(q_min, q), q_max = std::max(q_max, q);
  REQUIRE(q_max / q_min > 900.0);
  reference::NeighbourCache cache;
  for (int step = 0; step < 300; ++step) {
    INFO("step " << step);
    require_same(p, 1.5, cache, 16);
    jiggle(p, rng, 0.005, 0.02);
  }
  CHECK(cache.rebuilds() > 1);
  CHECK(cache.rebuilds() < 300);
}

TEST_CASE("neighbour cache rebuilds on count, kind, cutoff and invalid nodes", "[sim][perf]") {
  std::mt19937_64 rng(93);
  SimParticles p = random_uniform(rng, 300);
  reference::NeighbourCache cache;
  // The first call of a new set builds exactly; the second builds candidates; the third reuses them.
  require_same(p, 1.5, cache, 8);
  CHECK(cache.rebuilds() == 0);
  require_same(p, 1.5, cache, 8);
  CHECK(cache.rebuilds() == 1);
  require_same(p, 1.5, cache, 8);
  CHECK(cache.rebuilds() == 1);
  // A kind change: a former Fixed node now has a list.
  p.kind[1] = kSimInterior;
  require_same(p, 1.5, cache, 8);
  require_same(p, 1.5, cache, 8);
  CHECK(cache.rebuilds() == 2);
  // A boundary node (prev/next come from p every call).
  p.kind[5] = kSimBoundary;
  p.prev[5] = 4;
  p.next[5] = 6;
  require_same(p, 1.5, cache, 8);
  // Nodes appended near existing ones, then removed again.
  add(p, p.x[10] + 0.01, p.y[10], 0.5);
  add(p, p.x[20], p.y[20], 0.5);
  require_same(p, 1.5, cache, 8);
  p.resize(p.size() - 2);
  require_same(p, 1.5, cache, 8);
  // A larger cutoff, and one spacing grown past the growth bound.
  require_same(p, 3.0, cache, 8);
  p.q[7] *= 1.5;
  require_same(p, 3.0, cache, 8);
  // Nodes swapped: same count and kinds, positions exchanged.
  std::swap(p.x[30], p.x[40]);
  std::swap(p.y[30], p.y[40]);
  require_same(p, 3.0, cache, 8);
  // Invalid node: reported like the exact build, then the cache recovers.
  const double saved = p.x[9];
  p.x[9] = NAN;
  require_same(p, 3.0, cache, 8);
  p.x[9] = saved;
  require_same(p, 3.0, cache, 8);
  // Overflow at a small stride is reported the same way.
  require_same(p, 3.0, cache, 2);
}

TEST_CASE("reference backend: lists through build_neighbours_growing equal the exact build while moving",
          "[sim][perf]") {
  std::mt19937_64 rng(5);
  SimParticles p = random_uniform(rng, 500);
  auto backend = make_reference_backend();
  NeighbourList list;
  NeighbourFlags flags;
  for (int step = 0; step < 100; ++step) {
    INFO("step " << step);
    build_neighbours_growing(*backend, p, 1.5, list, flags);
    NeighbourList exact;
    exact.stride = list.stride;
    NeighbourFlags ef;
    reference::build_neighbours(p, 1.5, exact, ef);
    REQUIRE(list.count == exact.count);
    REQUIRE(list.index == exact.index);
    jiggle(p, rng, 0.01, 0.01);
  }
}

TEST_CASE("neighbour cache: pairs moving together by just under the skin while q grows stay exact", "[sim][perf]") {
  // Pairs on a line at distances spread over [R, M + 2a] (R = cutoff q, M = R (1 + growth), a = skin R):
  // the worst case of the completeness argument. Each pair closes by just under 2a while one node's
  // q grows by just under the growth bound, so pairs up to M + 2a apart become neighbours without
  // a rebuild; then q grows past the bound and the cache must rebuild.
  const double cutoff = 1.5, skin = 0.1, growth = 0.05;
  const double r = cutoff, a = skin * r, m = r * (1.0 + growth);
  SimParticles p;
  const int pairs = 64;
  for (int k = 0; k < pairs; ++k) {
    const double d = r + (m - r + 2.0 * a) * (k + 0.5) / pairs;
    add(p, 10.0 * k, 0.0, 1.0);
    add(p, 10.0 * k + d, 0.0, 1.0);
  }
  reference::NeighbourCache cache(skin, growth);
  require_same(p, cutoff, cache, 8);
  require_same(p, cutoff, cache, 8);
  REQUIRE(cache.rebuilds() == 1);
  for (int k = 0; k < pairs; ++k) {
    p.x[2 * k] += 0.999 * a;
    p.x[2 * k + 1] -= 0.999 * a;
    p.q[2 * k] *= 1.0 + 0.999 * growth;
  }
  NeighbourList list;
  NeighbourFlags flags;
  reference::build_neighbours(p, cutoff, list, flags);
  CHECK(flags.pairs_within > 2 * pairs / 2);  // most pairs (all of one side) are neighbours now
  require_same(p, cutoff, cache, 8);
  CHECK(cache.rebuilds() == 1);
  for (int k = 0; k < pairs; ++k) p.q[2 * k + 1] *= 1.0 + 2.0 * growth;
  require_same(p, cutoff, cache, 8);
  CHECK(cache.rebuilds() == 2);
}
