// Flat multi-level hashed cell grids for the device neighbour build; see neighbour_grids.hpp.
#include "opencl/neighbour_grids.hpp"

#include <algorithm>
#include <cmath>

namespace pdmesh::ocl {
namespace {

std::int64_t cell_coord(double v, double inv_cell) {
  const double c = std::floor(v * inv_cell);
  return static_cast<std::int64_t>(std::clamp(c, -4.0e18, 4.0e18));
}

// Appends one grid over `members` (ascending node indices) to the flat arrays. The hash table is
// sized by occupied cells (grown while filling), not by members: a coarse cumulative grid over many
// fine nodes has few cells, which keeps device memory O(N x levels x 4 bytes) plus O(cells).
void append_grid(const double* x, const double* y, const std::vector<std::int32_t>& members, double cell,
                 NeighbourGrids& g, std::size_t grid) {
  const double inv_cell = 1.0 / cell;
  std::size_t cap = 16;
  std::vector<std::int64_t> kx(cap), ky(cap);
  std::vector<std::int32_t> kid(cap, -1);
  auto place = [&](std::int64_t cx, std::int64_t cy, std::int32_t id) {
    for (std::size_t s = cell_hash(cx, cy) & (cap - 1);; s = (s + 1) & (cap - 1)) {
      if (kid[s] < 0) {
        kx[s] = cx;
        ky[s] = cy;
        kid[s] = id;
        return id;
      }
      if (kx[s] == cx && ky[s] == cy) return kid[s];
    }
  };
  std::vector<std::int32_t> cell_of(members.size());
  std::int32_t cells = 0;
  for (std::size_t m = 0; m < members.size(); ++m) {
    const auto j = static_cast<std::size_t>(members[m]);
    const std::int64_t cx = cell_coord(x[j], inv_cell), cy = cell_coord(y[j], inv_cell);
    if (2 * static_cast<std::size_t>(cells) + 2 > cap) {  // keep the load factor at most 1/2
      std::vector<std::int64_t> ox, oy;
      std::vector<std::int32_t> oid;
      ox.swap(kx);
      oy.swap(ky);
      oid.swap(kid);
      cap *= 2;
      kx.assign(cap, 0);
      ky.assign(cap, 0);
      kid.assign(cap, -1);
      for (std::size_t s = 0; s < oid.size(); ++s)
        if (oid[s] >= 0) place(ox[s], oy[s], oid[s]);
    }
    const std::int32_t id = place(cx, cy, cells);
    if (id == cells) ++cells;
    cell_of[m] = id;
  }
  g.inv_cell[grid] = inv_cell;
  g.table_offset[grid] = static_cast<std::int32_t>(g.table_id.size());
  g.table_mask[grid] = static_cast<std::int32_t>(cap - 1);
  g.table_cx.insert(g.table_cx.end(), kx.begin(), kx.end());
  g.table_cy.insert(g.table_cy.end(), ky.begin(), ky.end());
  g.table_id.insert(g.table_id.end(), kid.begin(), kid.end());
  // Counting sort by cell keeps ascending node order within a cell (members are ascending).
  const std::size_t start_base = g.cell_start.size(), nodes_base = g.cell_nodes.size();
  g.start_offset[grid] = static_cast<std::int32_t>(start_base);
  g.nodes_offset[grid] = static_cast<std::int32_t>(nodes_base);
  g.cell_start.resize(start_base + static_cast<std::size_t>(cells) + 1, 0);
  std::int32_t* start = g.cell_start.data() + start_base;
  for (auto c : cell_of) ++start[c + 1];
  for (std::int32_t c = 0; c < cells; ++c) start[c + 1] += start[c];
  g.cell_nodes.resize(nodes_base + members.size());
  std::vector<std::int32_t> fill(start, start + cells);
  for (std::size_t m = 0; m < members.size(); ++m)
    g.cell_nodes[nodes_base + static_cast<std::size_t>(fill[static_cast<std::size_t>(cell_of[m])]++)] = members[m];
}

}  // namespace

std::size_t NeighbourGrids::bytes() const {
  return level.size() * 4 + inv_cell.size() * 8 + table_offset.size() * 16 + table_cx.size() * 16 +
         table_id.size() * 4 + cell_start.size() * 4 + cell_nodes.size() * 4;
}

void build_neighbour_grids(const double* x, const double* y, const double* q, std::size_t n, double radius_factor,
                           NeighbourGrids& g) {
  g = NeighbourGrids{};
  g.level.assign(n, 0);
  if (n == 0) return;
  double r_min = HUGE_VAL;
  for (std::size_t j = 0; j < n; ++j) r_min = std::min(r_min, radius_factor * q[j]);
  int top = 0;
  for (std::size_t j = 0; j < n; ++j) {
    int e = 0;
    std::frexp(radius_factor * q[j] / r_min, &e);  // ratio = m 2^e, m in [0.5, 1): floor(log2) = e - 1
    g.level[j] = std::max(0, e - 1);
    top = std::max(top, g.level[j]);
  }
  g.levels = top + 1;
  const std::size_t grids = 2 * static_cast<std::size_t>(g.levels);
  g.inv_cell.assign(grids, 0.0);
  g.table_offset.assign(grids, 0);
  g.table_mask.assign(grids, 0);
  g.start_offset.assign(grids, 0);
  g.nodes_offset.assign(grids, 0);
  std::vector<std::vector<std::int32_t>> exact(static_cast<std::size_t>(g.levels));
  for (std::size_t j = 0; j < n; ++j)
    exact[static_cast<std::size_t>(g.level[j])].push_back(static_cast<std::int32_t>(j));
  // The cumulative grid of level L grows from level L-1's by merging in level L (both ascending).
  std::vector<std::int32_t> cumulative, merged;
  for (std::size_t l = 0; l < exact.size(); ++l) {
    if (exact[l].empty()) continue;
    merged.resize(cumulative.size() + exact[l].size());
    std::merge(cumulative.begin(), cumulative.end(), exact[l].begin(), exact[l].end(), merged.begin());
    cumulative.swap(merged);
    const double cell = std::ldexp(r_min, static_cast<int>(l));
    append_grid(x, y, cumulative, cell, g, 2 * l);
    append_grid(x, y, exact[l], cell, g, 2 * l + 1);
  }
}

}  // namespace pdmesh::ocl
