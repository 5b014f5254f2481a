// Reference step 1: neighbour lists from multi-level hashed cell grids.
// Spacing may vary 1000x (airfoils), so one uniform grid sized by the largest cut-off would put
// thousands of fine nodes in one cell. Instead node j gets a level L(j) = floor(log2(R_j / R_min))
// (R = cutoff * q), so c_L = R_min 2^L <= R_j < 2 c_L, and grids of cell size c_L are built per level:
//   cumulative grid C_L: every node of level <= L;   exact grid E_L: the nodes of level L only.
// Interior node i of level l looks in C_l (finer and equal nodes) and E_M for each M > l (coarser
// nodes); the query box [x - R_i, x + R_i] spans at most 5 x 5 cells of C_l (R_i < 2 c_l) and 3 x 3
// of each coarser E_M (R_i < c_M). Cells half the band's top radius examine ~4x fewer candidates
// than cells of the full radius on graded input (measured: 3.7 vs 14.9 candidates per pair found).
// Cells live in an open-addressing hash keyed by integer cell coordinates, so empty cells cost
// nothing; nodes are grouped by counting sort, ascending within a cell (deterministic, O(N)).
#include <algorithm>
#include <cmath>
#include <cstdint>

#include "sim/reference/reference_backend.hpp"

namespace pdmesh::reference {
namespace {

struct CellKey {
  std::int64_t cx = 0, cy = 0;
  bool operator==(const CellKey&) const = default;
};

std::uint64_t hash_key(CellKey k) {
  // splitmix64 finaliser over both coordinates.
  std::uint64_t h = static_cast<std::uint64_t>(k.cx) * 0x9E3779B97F4A7C15ULL ^ static_cast<std::uint64_t>(k.cy);
  h ^= h >> 30;
  h *= 0xBF58476D1CE4E5B9ULL;
  h ^= h >> 27;
  h *= 0x94D049BB133111EBULL;
  h ^= h >> 31;
  return h;
}

// Cell coordinate of a coordinate; clamped so that absurd coordinates cannot overflow.
std::int64_t cell_coord(double v, double inv_cell) {
  const double c = std::floor(v * inv_cell);
  return static_cast<std::int64_t>(std::clamp(c, -4.0e18, 4.0e18));
}

// Open-addressing map from cell key to a dense cell id (ids in order of first insertion).
class CellTable {
 public:
  explicit CellTable(std::size_t expected) {
    std::size_t cap = 16;
    while (cap < 2 * expected + 1) cap *= 2;
    keys_.resize(cap);
    ids_.assign(cap, -1);
    mask_ = cap - 1;
  }
  int insert(CellKey k, int next_id) {
    for (std::size_t s = hash_key(k) & mask_;; s = (s + 1) & mask_) {
      if (ids_[s] < 0) {
        keys_[s] = k;
        ids_[s] = next_id;
        return next_id;
      }
      if (keys_[s] == k) return ids_[s];
    }
  }
  int find(CellKey k) const {
    for (std::size_t s = hash_key(k) & mask_;; s = (s + 1) & mask_) {
      if (ids_[s] < 0) return -1;
      if (keys_[s] == k) return ids_[s];
    }
  }

 private:
  std::vector<CellKey> keys_;
  std::vector<int> ids_;
  std::size_t mask_ = 0;
};

// One hashed grid: nodes grouped by cell, ascending node index within a cell.
struct Grid {
  double cell = 1.0;
  double inv_cell = 1.0;
  CellTable table{0};
  std::vector<std::int32_t> start;  // cells + 1 offsets into nodes
  std::vector<std::int32_t> nodes;

  Grid(const SimParticles& p, const std::vector<std::int32_t>& members, double cell_size)
      : cell(cell_size), inv_cell(1.0 / cell_size), table(members.size()) {
    std::vector<std::int32_t> cell_of(members.size());
    int cells = 0;
    for (std::size_t m = 0; m < members.size(); ++m) {
      const auto j = static_cast<std::size_t>(members[m]);
      const CellKey k{cell_coord(p.x[j], inv_cell), cell_coord(p.y[j], inv_cell)};
      const int id = table.insert(k, cells);
      if (id == cells) ++cells;
      cell_of[m] = id;
    }
    start.assign(static_cast<std::size_t>(cells) + 1, 0);
    for (auto c : cell_of) ++start[static_cast<std::size_t>(c) + 1];
    for (std::size_t c = 0; c < static_cast<std::size_t>(cells); ++c) start[c + 1] += start[c];
    nodes.resize(members.size());
    std::vector<std::int32_t> fill(start.begin(), start.end() - 1);
    for (std::size_t m = 0; m < members.size(); ++m) nodes[static_cast<std::size_t>(fill[static_cast<std::size_t>(cell_of[m])]++)] = members[m];
  }

  // Calls visit(j) for every node in the cells overlapping the box around (x, y) of half-width r.
  template <class Visit>
  void for_each_near(double x, double y, double r, Visit&& visit) const {
    const std::int64_t x0 = cell_coord(x - r, inv_cell), x1 = cell_coord(x + r, inv_cell);
    const std::int64_t y0 = cell_coord(y - r, inv_cell), y1 = cell_coord(y + r, inv_cell);
    for (std::int64_t cy = y0; cy <= y1; ++cy) {
      for (std::int64_t cx = x0; cx <= x1; ++cx) {
        const int id = table.find({cx, cy});
        if (id < 0) continue;
        for (auto k = start[static_cast<std::size_t>(id)]; k < start[static_cast<std::size_t>(id) + 1]; ++k)
          visit(nodes[static_cast<std::size_t>(k)]);
      }
    }
  }
};

bool valid_node(const SimParticles& p, std::size_t i) {
  return std::isfinite(p.x[i]) && std::isfinite(p.y[i]) && std::isfinite(p.q[i]) && p.q[i] > 0.0;
}

// Resets the list for n nodes and scans for invalid nodes; fills Boundary nodes' {prev, next}.
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

// Stores node i's candidates (sorted) into the padded list and updates the flags.
void store(std::size_t i, std::vector<std::int32_t>& found, NeighbourList& list, NeighbourFlags& flags) {
  std::sort(found.begin(), found.end());
  const auto count = static_cast<std::int32_t>(found.size());
  list.count[i] = count;
  flags.max_count = std::max(flags.max_count, count);
  flags.pairs_within += found.size();
  if (count > list.stride) flags.overflow = 1;
  const std::size_t base = i * static_cast<std::size_t>(list.stride);
  const std::size_t kept = std::min(found.size(), static_cast<std::size_t>(list.stride));
  for (std::size_t k = 0; k < kept; ++k) list.index[base + k] = found[k];
}

}  // namespace

void build_neighbours(const SimParticles& p, double cutoff, NeighbourList& list, NeighbourFlags& flags) {
  start_list(p, list, flags);
  const std::size_t n = p.size();
  if (n == 0 || flags.first_invalid >= 0) return;

  double r_min = HUGE_VAL;
  for (std::size_t j = 0; j < n; ++j) r_min = std::min(r_min, cutoff * p.q[j]);
  std::vector<int> level(n);
  int top = 0;
  for (std::size_t j = 0; j < n; ++j) {
    int e = 0;
    std::frexp(cutoff * p.q[j] / r_min, &e);  // ratio = m 2^e, m in [0.5, 1): floor(log2) = e - 1
    level[j] = std::max(0, e - 1);
    top = std::max(top, level[j]);
  }
  std::vector<std::vector<std::int32_t>> exact(static_cast<std::size_t>(top) + 1);
  for (std::size_t j = 0; j < n; ++j) exact[static_cast<std::size_t>(level[j])].push_back(static_cast<std::int32_t>(j));

  // Grids are built only for levels that hold nodes (interior queries need C_l for their own level).
  std::vector<std::unique_ptr<Grid>> cumulative(exact.size()), exact_grid(exact.size());
  std::vector<std::int32_t> members;
  for (std::size_t l = 0; l < exact.size(); ++l) {
    if (exact[l].empty()) continue;
    const double cell = std::ldexp(r_min, static_cast<int>(l));
    exact_grid[l] = std::make_unique<Grid>(p, exact[l], cell);
    members.clear();
    for (std::size_t j = 0; j < n; ++j)
      if (static_cast<std::size_t>(level[j]) <= l) members.push_back(static_cast<std::int32_t>(j));
    cumulative[l] = std::make_unique<Grid>(p, members, cell);
  }

  std::vector<std::int32_t> found;
  for (std::size_t i = 0; i < n; ++i) {
    if (p.kind[i] != kSimInterior) continue;
    found.clear();
    const double xi = p.x[i], yi = p.y[i], r = cutoff * p.q[i], r2 = r * r;
    auto test = [&](std::int32_t j) {
      if (static_cast<std::size_t>(j) == i) return;
      ++flags.pairs_examined;
      const double dx = p.x[static_cast<std::size_t>(j)] - xi, dy = p.y[static_cast<std::size_t>(j)] - yi;
      if (dx * dx + dy * dy <= r2) found.push_back(j);
    };
    const auto l = static_cast<std::size_t>(level[i]);
    cumulative[l]->for_each_near(xi, yi, r, test);
    for (std::size_t m = l + 1; m < exact.size(); ++m)
      if (exact_grid[m]) exact_grid[m]->for_each_near(xi, yi, r, test);
    store(i, found, list, flags);
  }
}

void build_neighbours_brute_force(const SimParticles& p, double cutoff, NeighbourList& list,
                                  NeighbourFlags& flags) {
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
    store(i, found, list, flags);
  }
}

}  // namespace pdmesh::reference
