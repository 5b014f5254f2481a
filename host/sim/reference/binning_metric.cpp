// Reference step 1 in metric mode (metric_pair.hpp): interior node i's neighbours are the j != i with
// rho_ij = |x_j - x_i| in the pair's metric <= cutoff. The criterion is symmetric, and a bubble is an
// ellipse up to aspect 1000s, so the search radius of node j is R_j = cutoff * h_j with h_j its largest
// size 1/sqrt(lambda_min): rho_ij <= cutoff implies |d| <= max(R_i, R_j) (pair_distance2). Node i of
// level l therefore searches C_l (levels <= l, radius < 2 c_l) out to max(R_i, 2 c_l) and each coarser
// E_M out to max(R_i, 2 c_M), and filters candidates exactly. The Verlet cache is not used here.
#include <algorithm>
#include <cmath>
#include <cstdint>

#include "core/interrupt.hpp"
#include "sim/reference/level_grids.hpp"
#include "sim/reference/metric_pair.hpp"
#include "sim/reference/reference_backend.hpp"

namespace pdmesh::reference {

void build_neighbours_metric(const SimParticles& p, double cutoff, NeighbourList& list, NeighbourFlags& flags) {
  start_list(p, list, flags);
  const std::size_t n = p.size();
  if (n == 0 || flags.first_invalid >= 0) return;
  std::vector<double> radius(n);
  for (std::size_t j = 0; j < n; ++j) radius[j] = cutoff * largest_size(p.m11[j], p.m12[j], p.m22[j]);
  const std::vector<Sym2> s = pair_factors(p);
  LevelGrids grids;
  grids.build(p, radius);
  const double c2 = cutoff * cutoff;
  // 2 c_L bounds the radii of level L up to the rounding of the level's ratio (a relative 1e-15);
  // the margin only adds candidates, which the exact filter drops.
  const double margin = 2.0 * (1.0 + 1e-12);
  std::vector<std::int32_t> found;
  for (std::size_t i = 0; i < n; ++i) {
    if ((i & 16383) == 0) check_interrupt();
    if (p.kind[i] != kSimInterior) continue;
    found.clear();
    const double xi = p.x[i], yi = p.y[i], ri = radius[i];
    auto test = [&](std::int32_t j) {
      if (static_cast<std::size_t>(j) == i) return;
      ++flags.pairs_examined;
      const auto uj = static_cast<std::size_t>(j);
      if (pair_distance2(s[i], s[uj], p.x[uj] - xi, p.y[uj] - yi) <= c2) found.push_back(j);
    };
    grids.for_each_near(
        xi, yi, static_cast<std::size_t>(grids.level(i)),
        [&](std::size_t l) { return std::max(ri, margin * grids.cell_size(l)); }, test);
    std::sort(found.begin(), found.end());
    store_sorted(i, found, list, flags);
  }
}

void build_neighbours_metric_brute_force(const SimParticles& p, double cutoff, NeighbourList& list,
                                         NeighbourFlags& flags) {
  start_list(p, list, flags);
  if (flags.first_invalid >= 0) return;
  const std::size_t n = p.size();
  const std::vector<Sym2> s = pair_factors(p);
  const double c2 = cutoff * cutoff;
  std::vector<std::int32_t> found;
  for (std::size_t i = 0; i < n; ++i) {
    if (p.kind[i] != kSimInterior) continue;
    found.clear();
    for (std::size_t j = 0; j < n; ++j) {
      if (j == i) continue;
      ++flags.pairs_examined;
      if (pair_distance2(s[i], s[j], p.x[j] - p.x[i], p.y[j] - p.y[i]) <= c2)
        found.push_back(static_cast<std::int32_t>(j));
    }
    store_sorted(i, found, list, flags);
  }
}

}  // namespace pdmesh::reference
