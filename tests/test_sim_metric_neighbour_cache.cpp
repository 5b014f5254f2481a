// The Verlet candidate cache of metric mode (metric_neighbour_cache.hpp) against the exact build
// (reference::build_neighbours_metric): identical lists and flags at every step while nodes move and
// their metrics turn, stretch and jump, with counts, kinds and conditioning changing.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdint>
#include <random>

#include "sim/reference/metric_neighbour_cache.hpp"
#include "sim/reference/reference_backend.hpp"
#include "neighbour_list_checks.hpp"
#include "sim_fixtures.hpp"

using namespace pdmesh;
using pdmesh_test::add;
using pdmesh_test::set_sizes;
using pdmesh_test::uniform;

namespace {

void require_same(const SimParticles& p, double cutoff, reference::MetricNeighbourCache& cache, int stride) {
  pdmesh_test::require_same_lists(p, cutoff, cache, stride, reference::build_neighbours_metric);
}

// A node's sizes and direction, from which its metric is set.
struct Bubble {
  double h1 = 0.0, h2 = 0.0, angle = 0.0;
};

// A layer along y = 0.5 + 0.25 sin(2 pi x) in [0, 1]^2: nodes near the curve stretched along it (aspect
// up to 100), the others isotropic, and one node in 50 fixed or on a boundary.
SimParticles curved_layer(std::mt19937_64& rng, std::size_t n, std::vector<Bubble>& bubbles) {
  SimParticles p;
  bubbles.assign(n, {});
  for (std::size_t i = 0; i < n; ++i) {
    const double x = uniform(rng);
    const double across = i % 3 == 0 ? uniform(rng) - 0.5 : 0.02 * (uniform(rng) - 0.5);
    const double y = 0.5 + 0.25 * std::sin(2.0 * M_PI * x) + across;
    add(p, x, y, 1.0, i % 50 == 0 ? kSimFixed : kSimInterior);
    const double along = std::atan(0.5 * M_PI * std::cos(2.0 * M_PI * x));
    const double h = 0.03, thin = std::min(h, 0.0003 + 0.1 * std::fabs(across));
    bubbles[i] = {h, thin, along};
  }
  for (std::size_t i = 25; i + 1 < n; i += 50) {
    p.kind[i] = kSimBoundary;
    p.prev[i] = static_cast<int>(i - 1);
    p.next[i] = static_cast<int>(i + 1);
  }
  for (std::size_t i = 0; i < n; ++i) set_sizes(p, i, bubbles[i].h1, bubbles[i].h2, bubbles[i].angle);
  return p;
}

// Every free node moves by up to `step` of its sizes along its axes, its bubble turns by up to `turn`
// and its sizes change by up to `stretch` (relative); `jumps` nodes jump by 10 sizes and have their
// sizes halved or doubled.
void stir(SimParticles& p, std::vector<Bubble>& bubbles, std::mt19937_64& rng, double step, double turn, double stretch,
          int jumps) {
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (p.kind[i] == kSimFixed) continue;
    Bubble& b = bubbles[i];
    const double c = std::cos(b.angle), s = std::sin(b.angle);
    const double a1 = step * b.h1 * (2.0 * uniform(rng) - 1.0), a2 = step * b.h2 * (2.0 * uniform(rng) - 1.0);
    p.x[i] += a1 * c - a2 * s;
    p.y[i] += a1 * s + a2 * c;
    b.angle += turn * (2.0 * uniform(rng) - 1.0);
    b.h1 *= 1.0 + stretch * (2.0 * uniform(rng) - 1.0);
    b.h2 *= 1.0 + stretch * (2.0 * uniform(rng) - 1.0);
  }
  for (int k = 0; k < jumps; ++k) {
    const std::size_t i = rng() % p.size();
    Bubble& b = bubbles[i];
    p.x[i] += 10.0 * b.h2 * std::cos(b.angle + 0.5 * M_PI);
    p.y[i] += 10.0 * b.h2 * std::sin(b.angle + 0.5 * M_PI);
    const double f = rng() % 2 == 0 ? 0.5 : 2.0;
    b.h1 *= f;
    b.h2 *= f;
  }
  for (std::size_t i = 0; i < p.size(); ++i) set_sizes(p, i, bubbles[i].h1, bubbles[i].h2, bubbles[i].angle);
}

}  // namespace

TEST_CASE("metric neighbour cache equals the exact build: a curved layer moving, turning and stretching",
          "[sim][metric][neighbours]") {
  std::mt19937_64 rng(11);
  std::vector<Bubble> bubbles;
  SimParticles p = curved_layer(rng, 1200, bubbles);
  reference::MetricNeighbourCache cache;
  for (int step = 0; step < 160; ++step) {
    INFO("step " << step);
    require_same(p, 1.5, cache, 64);
    // Quiet steps, steps with a few nodes jumping (rebased), and every 40th step all of them moving far.
    const bool far = step % 40 == 39;
    stir(p, bubbles, rng, far ? 0.5 : 0.01, far ? 0.2 : 1e-4, far ? 0.2 : 0.002, step % 5 == 0 ? 3 : 0);
  }
  // The candidates must be reused, rebased and rebuilt for this test to test them.
  INFO("rebuilds " << cache.rebuilds() << ", nodes rebased " << cache.rebased());
  CHECK(cache.rebuilds() >= 4);
  CHECK(cache.rebuilds() < 80);
  CHECK(cache.rebased() > 0);
}

TEST_CASE("metric neighbour cache equals the exact build with a few nodes rebased and with many",
          "[sim][metric][neighbours]") {
  // A few rebased nodes scan every stored state for their candidates; more than kScanRebased (32)
  // search the rebuilt box search: both must keep the lists exact.
  std::mt19937_64 rng(5);
  std::vector<Bubble> bubbles;
  SimParticles p = curved_layer(rng, 1500, bubbles);
  reference::MetricNeighbourCache cache;
  require_same(p, 1.5, cache, 64);
  require_same(p, 1.5, cache, 64);
  REQUIRE(cache.rebuilds() == 1);
  std::uint64_t rebased = 0;
  for (const int jumps : {2, 40, 1, 100, 5, 60}) {
    INFO("jumps " << jumps);
    stir(p, bubbles, rng, 0.005, 1e-5, 1e-4, jumps);
    require_same(p, 1.5, cache, 64);
    CHECK(cache.rebuilds() == 1);
    // Each jumping node is rebased (a node may jump twice, and a quiet one may not need it).
    CHECK(cache.rebased() - rebased > 0);
    CHECK(cache.rebased() - rebased <= static_cast<std::uint64_t>(jumps));
    rebased = cache.rebased();
  }
}

TEST_CASE("metric neighbour cache: pairs closing by just under the skin while their bubbles grow stay exact",
          "[sim][metric][neighbours]") {
  // Isotropic bubbles M = I / q^2 in pairs on a line at distances spread over [c q, (1 + growth + 2 skin) c q):
  // each node moves towards its partner by just under skin c q and both bubbles grow by just under
  // 1 + growth, which is the most the bound allows without a rebuild, and makes them all neighbours.
  const double cutoff = 1.5, skin = 0.1, growth = 0.05, q = 1.0;
  SimParticles p;
  const int pairs = 64;
  for (int k = 0; k < pairs; ++k) {
    const double d = cutoff * q * (1.0 + (growth + 2.0 * skin) * (k + 0.5) / pairs);
    add(p, 10.0 * k, 0.0, q);
    add(p, 10.0 * k + d, 0.0, q);
  }
  for (std::size_t i = 0; i < p.size(); ++i) set_sizes(p, i, q, q, 0.0);
  reference::MetricNeighbourCache cache(skin, growth);
  require_same(p, cutoff, cache, 8);
  require_same(p, cutoff, cache, 8);
  REQUIRE(cache.rebuilds() == 1);
  const double move = 0.999 * skin * cutoff * q, grown = q * (1.0 + 0.999 * growth);
  for (int k = 0; k < pairs; ++k) {
    p.x[2 * k] += move;
    p.x[2 * k + 1] -= move;
  }
  for (std::size_t i = 0; i < p.size(); ++i) set_sizes(p, i, grown, grown, 0.0);
  NeighbourList list;
  NeighbourFlags flags;
  reference::build_neighbours_metric(p, cutoff, list, flags);
  CHECK(flags.pairs_within == 2 * pairs);  // every pair is a pair of neighbours now
  require_same(p, cutoff, cache, 8);
  CHECK(cache.rebuilds() == 1);
  CHECK(cache.rebased() == 0);
  // One node's bubble grows past the bound: it alone is rebased.
  set_sizes(p, 7, q * (1.0 + 3.0 * growth), q * (1.0 + 3.0 * growth), 0.0);
  require_same(p, cutoff, cache, 8);
  CHECK(cache.rebuilds() == 1);
  CHECK(cache.rebased() == 1);
  // Every node moves past the skin after the candidates served 4 calls: a rebuild.
  require_same(p, cutoff, cache, 8);
  const auto move_all = [&] {
    for (std::size_t i = 0; i < p.size(); ++i) p.x[i] += 2.0 * skin * cutoff * q * (i % 2 == 0 ? 1.0 : -1.0);
  };
  move_all();
  require_same(p, cutoff, cache, 8);
  CHECK(cache.rebuilds() == 2);
  // Past the skin again at once: that rebuild did not pay, so this call builds exactly and the next
  // one tries candidates again; after a second such rebuild, two calls build exactly.
  move_all();
  require_same(p, cutoff, cache, 8);
  CHECK(cache.rebuilds() == 2);
  require_same(p, cutoff, cache, 8);
  CHECK(cache.rebuilds() == 3);
  move_all();
  require_same(p, cutoff, cache, 8);
  require_same(p, cutoff, cache, 8);
  CHECK(cache.rebuilds() == 3);
  require_same(p, cutoff, cache, 8);
  CHECK(cache.rebuilds() == 4);
}

TEST_CASE("metric neighbour cache follows count, kind and cutoff changes and badly conditioned metrics",
          "[sim][metric][neighbours]") {
  std::mt19937_64 rng(5);
  std::vector<Bubble> bubbles;
  SimParticles p = curved_layer(rng, 400, bubbles);
  reference::MetricNeighbourCache cache;
  // The first call of a new set builds exactly; the second builds candidates; the third reuses them.
  require_same(p, 1.5, cache, 64);
  CHECK(cache.rebuilds() == 0);
  require_same(p, 1.5, cache, 64);
  CHECK(cache.rebuilds() == 1);
  require_same(p, 1.5, cache, 64);
  CHECK(cache.rebuilds() == 1);
  // A kind change, a cutoff change, nodes appended and removed: exact builds, then candidates again.
  p.kind[0] = kSimInterior;
  require_same(p, 1.5, cache, 64);
  require_same(p, 1.5, cache, 64);
  CHECK(cache.rebuilds() == 2);
  require_same(p, 1.7, cache, 64);
  require_same(p, 1.7, cache, 64);
  CHECK(cache.rebuilds() == 3);
  for (int k = 0; k < 5; ++k) {
    add(p, p.x[static_cast<std::size_t>(k)] + 0.001, p.y[static_cast<std::size_t>(k)], 1.0);
    set_sizes(p, p.size() - 1, 0.03, 0.001, 0.3);
  }
  for (int step = 0; step < 4; ++step) require_same(p, 1.7, cache, 64);
  CHECK(cache.rebuilds() == 4);
  // An aspect ratio of 1e6 (condition 1e12): the bound's rounding margin does not cover it, so every
  // call builds exactly, and the lists still agree as the nodes move.
  set_sizes(p, 3, 0.1, 1e-7, 0.7);
  for (int step = 0; step < 6; ++step) {
    INFO("step " << step);
    require_same(p, 1.7, cache, 64);
    p.x[10] += 1e-4;
  }
  CHECK(cache.rebuilds() == 4);
  // A node with an invalid metric is reported as the exact build reports it.
  p.m11[20] = -1.0;
  require_same(p, 1.7, cache, 64);
}
