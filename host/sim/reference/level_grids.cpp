// The multi-level hashed cell grids of the reference neighbour search, and the shared list helpers.
#include "sim/reference/level_grids.hpp"

#include <algorithm>
#include <cmath>

#include "sim/cell_hash.hpp"
#include "sim/reference/metric_pair.hpp"

namespace pdmesh::reference {

// Cell coordinate of a coordinate; clamped so that absurd coordinates cannot overflow.
std::int64_t cell_coord(double v, double inv_cell) {
  const double c = std::floor(v * inv_cell);
  return static_cast<std::int64_t>(std::clamp(c, -4.0e18, 4.0e18));
}

int LevelGrids::Grid::find(std::int64_t cx, std::int64_t cy) const {
  for (std::size_t s = cell_hash(cx, cy) & mask;; s = (s + 1) & mask) {
    const int id = slot_id[s];
    if (id < 0) return -1;
    if (key_x[s] == cx && key_y[s] == cy) return id;
  }
}

void LevelGrids::Grid::build(const SimParticles& p, const std::vector<std::int32_t>& members, double cell_size) {
  build(p.x, p.y, members, cell_size, cell_size);
}

void LevelGrids::Grid::build(const std::vector<double>& x, const std::vector<double>& y,
                             const std::vector<std::int32_t>& members, double cell_x, double cell_y) {
  inv_cell = 1.0 / cell_x;
  inv_cell_y = 1.0 / cell_y;
  std::size_t cap = 16;
  while (cap < 2 * members.size() + 1) cap *= 2;
  key_x.resize(cap);
  key_y.resize(cap);
  slot_id.assign(cap, -1);
  mask = cap - 1;
  cell_of.resize(members.size());
  std::int32_t cells = 0;
  for (std::size_t m = 0; m < members.size(); ++m) {
    const auto j = static_cast<std::size_t>(members[m]);
    const std::int64_t cx = cell_coord(x[j], inv_cell), cy = cell_coord(y[j], inv_cell_y);
    std::size_t s = cell_hash(cx, cy) & mask;
    while (slot_id[s] >= 0 && !(key_x[s] == cx && key_y[s] == cy)) s = (s + 1) & mask;
    if (slot_id[s] < 0) {
      key_x[s] = cx;
      key_y[s] = cy;
      slot_id[s] = cells++;
    }
    cell_of[m] = slot_id[s];
  }
  start.assign(static_cast<std::size_t>(cells) + 1, 0);
  for (auto c : cell_of) ++start[static_cast<std::size_t>(c) + 1];
  for (std::size_t c = 0; c < static_cast<std::size_t>(cells); ++c) start[c + 1] += start[c];
  nodes.resize(members.size());
  // Fill back to front with decrementing ends: ascending members stay ascending within a cell.
  for (std::size_t m = members.size(); m-- > 0;)
    nodes[static_cast<std::size_t>(--start[static_cast<std::size_t>(cell_of[m]) + 1])] = members[m];
  // start[c + 1] now holds the first slot of cell c: shift left by one.
  std::rotate(start.begin(), start.begin() + 1, start.end());
  start.back() = static_cast<std::int32_t>(members.size());
}

int size_level(double ratio) {
  int e = 0;
  std::frexp(ratio, &e);  // ratio = m 2^e, m in [0.5, 1): floor(log2) = e - 1
  return std::max(0, e - 1);
}

void LevelGrids::build(const SimParticles& p, const std::vector<double>& radius) {
  const std::size_t n = p.size();
  double r_min = HUGE_VAL;
  for (std::size_t j = 0; j < n; ++j) r_min = std::min(r_min, radius[j]);
  r_min_ = r_min;
  level_.resize(n);
  int top = 0;
  for (std::size_t j = 0; j < n; ++j) {
    level_[j] = size_level(radius[j] / r_min);
    top = std::max(top, level_[j]);
  }
  const std::size_t levels = n == 0 ? 0 : static_cast<std::size_t>(top) + 1;
  members_.resize(levels);
  for (auto& m : members_) m.clear();
  for (std::size_t j = 0; j < n; ++j)
    members_[static_cast<std::size_t>(level_[j])].push_back(static_cast<std::int32_t>(j));
  cumulative_.resize(levels);
  exact_.resize(levels);
  for (std::size_t l = 0; l < levels; ++l) {
    // Grids only for occupied levels (a query of level l needs C_l, and l is occupied).
    if (members_[l].empty()) {
      exact_[l].nodes.clear();
      cumulative_[l].nodes.clear();
      continue;
    }
    const double cell = std::ldexp(r_min, static_cast<int>(l));
    exact_[l].build(p, members_[l], cell);
    cumulative_members_.clear();
    for (std::size_t j = 0; j < n; ++j)
      if (static_cast<std::size_t>(level_[j]) <= l) cumulative_members_.push_back(static_cast<std::int32_t>(j));
    cumulative_[l].build(p, cumulative_members_, cell);
  }
}

bool valid_node(const SimParticles& p, std::size_t i) {
  if (p.has_metric())
    return std::isfinite(p.x[i]) && std::isfinite(p.y[i]) && valid_metric(p.m11[i], p.m12[i], p.m22[i]);
  return std::isfinite(p.x[i]) && std::isfinite(p.y[i]) && std::isfinite(p.q[i]) && p.q[i] > 0.0;
}

void start_list(const SimParticles& p, NeighbourList& list, NeighbourFlags& flags) {
  const std::size_t n = p.size();
  flags = NeighbourFlags{};
  if (list.stride < 2) list.stride = 2;
  list.count.assign(n, 0);
  list.index.assign(n * static_cast<std::size_t>(list.stride), -1);
  for (std::size_t i = 0; i < n; ++i) {
    if (flags.first_invalid < 0 && !valid_node(p, i)) flags.first_invalid = static_cast<std::int32_t>(i);
    if (p.kind[i] == kSimBoundary) {
      const std::size_t base = i * static_cast<std::size_t>(list.stride);
      list.index[base] = p.prev[i];
      list.index[base + 1] = p.next[i];
      list.count[i] = 2;
      flags.max_count = std::max(flags.max_count, 2);
    }
  }
}

void store_row(std::size_t i, const std::vector<std::int32_t>& found, NeighbourList& list) {
  list.count[i] = static_cast<std::int32_t>(found.size());
  const std::size_t base = i * static_cast<std::size_t>(list.stride);
  const std::size_t kept = std::min(found.size(), static_cast<std::size_t>(list.stride));
  std::copy_n(found.begin(), kept, list.index.begin() + static_cast<std::ptrdiff_t>(base));
}

void add_row_flags(std::int32_t count, const NeighbourList& list, NeighbourFlags& flags) {
  flags.max_count = std::max(flags.max_count, count);
  flags.pairs_within += static_cast<std::uint64_t>(count);
  if (count > list.stride) flags.overflow = 1;
}

void store_sorted(std::size_t i, const std::vector<std::int32_t>& found, NeighbourList& list, NeighbourFlags& flags) {
  store_row(i, found, list);
  add_row_flags(list.count[i], list, flags);
}

}  // namespace pdmesh::reference
