// Reference step 1 in metric mode (metric_pair.hpp): interior node i's neighbours are the j != i with
// rho_ij = |x_j - x_i| in the pair's metric <= cutoff. The criterion is symmetric, and a bubble is an
// ellipse up to aspect 1000s. The candidates are metric_search.hpp's box search (every pair within the
// cut-off is in it), filtered exactly (pair_distance2). The rows are built on every core, each from its
// own node's search, so the list does not depend on the thread count. The Verlet candidates of
// metric_neighbour_cache.cpp reuse the search with a margin.
#include <algorithm>
#include <cmath>
#include <cstdint>

#include "core/interrupt.hpp"
#include "core/parallel.hpp"
#include "sim/reference/level_grids.hpp"
#include "sim/reference/metric_pair.hpp"
#include "sim/reference/metric_search.hpp"
#include "sim/reference/reference_backend.hpp"

namespace pdmesh::reference {

void build_neighbours_metric(const SimParticles& p, double cutoff, NeighbourList& list, NeighbourFlags& flags) {
  start_list(p, list, flags);
  const std::size_t n = p.size();
  if (n == 0 || flags.first_invalid >= 0) return;
  const std::vector<Sym2> s = pair_factors(p);
  MetricBoxSearch search;
  search.build(p, MetricFrame::of(p, s), cutoff, 1.0);
  const double c2 = cutoff * cutoff;
  std::vector<std::uint64_t> examined(n, 0);
  struct Scratch {
    std::vector<std::int32_t> found;
  };
  parallel_for_scratch<Scratch>(
      n,
      [&](Scratch& scratch, std::size_t i) {
        if (p.kind[i] != kSimInterior) return;
        std::vector<std::int32_t>& found = scratch.found;
        found.clear();
        examined[i] = search.for_each_in_box(i, [&](std::int32_t j) {
          const auto uj = static_cast<std::size_t>(j);
          if (pair_distance2(s[i], s[uj], p.x[uj] - p.x[i], p.y[uj] - p.y[i]) <= c2) found.push_back(j);
        });
        std::sort(found.begin(), found.end());
        // Each row has its own slots in the list; the flags are summed below, in node order.
        store_row(i, found, list);
      },
      256);
  for (std::size_t i = 0; i < n; ++i) {
    if (p.kind[i] != kSimInterior) continue;
    flags.pairs_examined += examined[i];
    add_row_flags(list.count[i], list, flags);
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
