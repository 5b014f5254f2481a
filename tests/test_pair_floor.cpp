// The pair-force floor (sim/pair_floor.hpp): the lattice and its cells, the pair counts against brute
// force, both loops' forces and moves against a brute-force sum over all pairs, and bad options.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdint>
#include <vector>

#include "core/errors.hpp"
#include "sim/pair_floor.hpp"

using namespace pdmesh;

namespace {

FloorOptions small(std::size_t nodes) {
  FloorOptions o;
  o.nodes = nodes;
  o.repeats = 1;
  return o;
}

// Every pair within the cut-off by brute force: counts and node i's force (eq. 5.11, sigma the mean q).
struct Brute {
  std::uint64_t within = 0;
  std::vector<double> fx, fy;
};
Brute brute_force(const FloorLattice& l) {
  Brute b;
  const std::size_t n = l.size();
  b.fx.assign(n, 0.0);
  b.fy.assign(n, 0.0);
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = 0; j < n; ++j) {
      const double dx = l.x[j] - l.x[i], dy = l.y[j] - l.y[i], r2 = dx * dx + dy * dy;
      const double rc = l.cutoff * l.q[i];
      if (!(r2 > 0.0 && r2 <= rc * rc)) continue;
      ++b.within;
      const double sigma = 0.5 * (l.q[i] + l.q[j]), s6 = std::pow(sigma * sigma / r2, 3);
      const double f = -4.0 * l.lj_a * sigma * (s6 * s6 - s6) / std::sqrt(r2);
      b.fx[i] += f * dx;
      b.fy[i] += f * dy;
    }
  return b;
}

}  // namespace

TEST_CASE("floor lattice: exactly N nodes, sorted by cells no smaller than the cut-off") {
  for (const std::size_t n : {2u, 7u, 64u, 65u, 997u, 5000u}) {
    const FloorLattice l = make_floor_lattice(small(n));
    REQUIRE(l.size() == n);
    REQUIRE(l.cell >= l.cutoff * 1.0);
    REQUIRE(l.cell_start.size() == l.cells_x * l.cells_y + 1);
    REQUIRE(l.cell_start.front() == 0);
    REQUIRE(l.cell_start.back() == n);
    for (std::size_t c = 0; c + 1 < l.cell_start.size(); ++c)
      for (std::uint32_t i = l.cell_start[c]; i < l.cell_start[c + 1]; ++i) {
        const auto cx = std::min(l.cells_x - 1, static_cast<std::size_t>((l.x[i] - l.x0) / l.cell));
        const auto cy = std::min(l.cells_y - 1, static_cast<std::size_t>((l.y[i] - l.y0) / l.cell));
        REQUIRE(cy * l.cells_x + cx == c);
      }
  }
}

TEST_CASE("floor lattice: the same seed gives the same nodes, another seed others") {
  FloorOptions o = small(500);
  const FloorLattice a = make_floor_lattice(o), b = make_floor_lattice(o);
  REQUIRE(a.x == b.x);
  REQUIRE(a.y == b.y);
  o.seed = 2;
  REQUIRE(make_floor_lattice(o).x != a.x);
}

TEST_CASE("floor counts: pairs within the cut-off as brute force, and six per node on a settled lattice") {
  FloorOptions o = small(3000);
  o.jitter = 0.0;
  const FloorLattice l = make_floor_lattice(o);
  const FloorCounts c = count_floor_pairs(l);
  REQUIRE(c.within == brute_force(l).within);
  // Edges 0.91 q, the next ring at 0.91 sqrt(3) q = 1.58 q beyond the cut-off 1.5 q: six within, less
  // at the lattice's rim.
  const double per_node = static_cast<double>(c.within) / 3000.0;
  REQUIRE(per_node < 6.0);
  REQUIRE(per_node > 5.5);
  REQUIRE(c.candidates > c.within);
  REQUIRE(make_floor_lattice(small(3000)).size() == 3000);
  o.jitter = 0.05;
  const FloorLattice jittered = make_floor_lattice(o);
  REQUIRE(count_floor_pairs(jittered).within == brute_force(jittered).within);
}

TEST_CASE("floor iteration: both loops move every node by dt^2/2 F of the brute-force sum") {
  for (const std::size_t n : {2u, 65u, 1500u}) {
    const FloorLattice l = make_floor_lattice(small(n));
    const Brute b = brute_force(l);
    const double dt2 = 1e-3;
    for (const FloorLoop loop : {FloorLoop::Scalar, FloorLoop::Vector}) {
      for (const std::size_t threads : {std::size_t{1}, std::size_t{0}}) {
        std::vector<double> nx, ny;
        floor_iteration(l, loop, dt2, nx, ny, threads);
        REQUIRE(nx.size() == n);
        for (std::size_t i = 0; i < n; ++i) {
          const double scale = std::max(1.0, std::abs(b.fx[i]) + std::abs(b.fy[i]));
          INFO("node " << i << " loop " << static_cast<int>(loop) << " threads " << threads);
          REQUIRE(std::abs((nx[i] - l.x[i]) / (0.5 * dt2) - b.fx[i]) <= 1e-9 * scale);
          REQUIRE(std::abs((ny[i] - l.y[i]) / (0.5 * dt2) - b.fy[i]) <= 1e-9 * scale);
        }
      }
    }
  }
}

TEST_CASE("floor measurement: counts, bytes and times of both loops") {
  FloorOptions o = small(2000);
  o.repeats = 2;
  const FloorResult r = measure_pair_floor(o);
  REQUIRE(r.nodes == 2000);
  REQUIRE(r.threads >= 1);
  REQUIRE(r.bytes >= 40.0 * 2000);
  REQUIRE(r.scalar.wall > 0.0);
  REQUIRE(r.vector.wall > 0.0);
  REQUIRE(r.seconds() == std::min(r.scalar.wall, r.vector.wall));
  REQUIRE_FALSE(r.isa.empty());
  REQUIRE(format_floor(r).find("2000 nodes") != std::string::npos);
}

TEST_CASE("floor options out of range are refused naming the value") {
  FloorOptions o = small(1);
  REQUIRE_THROWS_WITH(make_floor_lattice(o), Catch::Contains("nodes") && Catch::Contains("1"));
  o = small(100);
  o.cutoff = 0.0;
  REQUIRE_THROWS_AS(make_floor_lattice(o), InputError);
  o = small(100);
  o.jitter = 0.5;
  REQUIRE_THROWS_WITH(make_floor_lattice(o), Catch::Contains("jitter"));
  o = small(100);
  o.repeats = 0;
  REQUIRE_THROWS_WITH(measure_pair_floor(o), Catch::Contains("repeats"));
  o = small(100);
  o.spacing_ratio = std::nan("");
  REQUIRE_THROWS_WITH(make_floor_lattice(o), Catch::Contains("spacing ratio"));
}
