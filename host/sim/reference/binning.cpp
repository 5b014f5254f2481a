// Reference step 1: exact neighbour lists from multi-level hashed cell grids (level_grids.hpp).
// Spacing may vary 1000x (airfoils), so one uniform grid sized by the largest cut-off would put
// thousands of fine nodes in one cell. Instead node j gets a level L(j) = floor(log2(R_j / R_min))
// (R = cutoff * q), so c_L = R_min 2^L <= R_j < 2 c_L. Interior node i of level l looks in C_l
// (finer and equal nodes) and E_M for each M > l (coarser nodes); the query box [x - R_i, x + R_i]
// spans at most 5 x 5 cells of C_l (R_i < 2 c_l) and 3 x 3 of each coarser E_M (R_i < c_M). Cells
// half the band's top radius examine ~4x fewer candidates than cells of the full radius on graded
// input (measured: 3.7 vs 14.9 candidates per pair found).
#include <algorithm>
#include <cmath>
#include <cstdint>

#include "sim/reference/level_grids.hpp"
#include "core/interrupt.hpp"
#include "sim/reference/reference_backend.hpp"

namespace pdmesh::reference {

void build_neighbours(const SimParticles& p, double cutoff, NeighbourList& list, NeighbourFlags& flags) {
  if (p.has_metric()) {
    build_neighbours_metric(p, cutoff, list, flags);
    return;
  }
  start_list(p, list, flags);
  const std::size_t n = p.size();
  if (n == 0 || flags.first_invalid >= 0) return;
  std::vector<double> radius(n);
  for (std::size_t j = 0; j < n; ++j) radius[j] = cutoff * p.q[j];
  LevelGrids grids;
  grids.build(p, radius);

  std::vector<std::int32_t> found;
  for (std::size_t i = 0; i < n; ++i) {
    if ((i & 16383) == 0) check_interrupt();
    if (p.kind[i] != kSimInterior) continue;
    found.clear();
    const double xi = p.x[i], yi = p.y[i], r = cutoff * p.q[i], r2 = r * r;
    auto test = [&](std::int32_t j) {
      if (static_cast<std::size_t>(j) == i) return;
      ++flags.pairs_examined;
      const double dx = p.x[static_cast<std::size_t>(j)] - xi, dy = p.y[static_cast<std::size_t>(j)] - yi;
      if (dx * dx + dy * dy <= r2) found.push_back(j);
    };
    grids.for_each_near(
        xi, yi, static_cast<std::size_t>(grids.level(i)), [r](std::size_t) { return r; }, test);
    std::sort(found.begin(), found.end());
    store_sorted(i, found, list, flags);
  }
}

void build_neighbours_brute_force(const SimParticles& p, double cutoff, NeighbourList& list, NeighbourFlags& flags) {
  if (p.has_metric()) {
    build_neighbours_metric_brute_force(p, cutoff, list, flags);
    return;
  }
  start_list(p, list, flags);
  if (flags.first_invalid >= 0) return;
  const std::size_t n = p.size();
  std::vector<std::int32_t> found;
  for (std::size_t i = 0; i < n; ++i) {
    if (p.kind[i] != kSimInterior) continue;
    found.clear();
    const double r = cutoff * p.q[i], r2 = r * r;
    for (std::size_t j = 0; j < n; ++j) {
      if (j == i) continue;
      ++flags.pairs_examined;
      const double dx = p.x[j] - p.x[i], dy = p.y[j] - p.y[i];
      if (dx * dx + dy * dy <= r2) found.push_back(static_cast<std::int32_t>(j));
    }
    store_sorted(i, found, list, flags);
  }
}

}  // namespace pdmesh::reference
