// The multi-level hashed cell grids behind the reference neighbour search (binning.cpp, and the
// Verlet candidate lists of neighbour_cache.cpp), and the list helpers both builders share.
#pragma once
#include <cmath>
#include <cstdint>
#include <vector>

#include "sim/step_backend.hpp"

namespace pdmesh::reference {

// Node j gets a level L(j) = floor(log2(radius_j / radius_min)), so c_L = radius_min 2^L <= radius_j
// < 2 c_L; per occupied level there is a cumulative grid C_L (every node of level <= L) and an exact
// grid E_L (the nodes of level L only), of cell size c_L. A query of level l visits C_l and E_M for
// every M > l, so every node is visited at most once per query whatever the query radius.
class LevelGrids {
 public:
  // Cells live in an open-addressing hash keyed by integer cell coordinates (empty cells cost
  // nothing); nodes are grouped by counting sort, ascending within a cell. Storage is reused.
  struct Grid {
    double inv_cell = 1.0, inv_cell_y = 1.0;  // cells are 1 / inv_cell along x, 1 / inv_cell_y along y
    std::vector<std::int64_t> key_x, key_y;   // hash slots: cell coordinates
    std::vector<std::int32_t> slot_id;        // hash slots: dense cell id, -1 = empty
    std::size_t mask = 0;
    std::vector<std::int32_t> start;  // cells + 1 offsets into nodes
    std::vector<std::int32_t> nodes;
    std::vector<std::int32_t> cell_of;  // scratch
    bool empty() const { return nodes.empty(); }
    void build(const SimParticles& p, const std::vector<std::int32_t>& members, double cell_size);
    // Cells of cell_x by cell_y over the points (x[j], y[j]) of the members.
    void build(const std::vector<double>& x, const std::vector<double>& y, const std::vector<std::int32_t>& members,
               double cell_x, double cell_y);
    int find(std::int64_t cx, std::int64_t cy) const;
    // Calls visit(j) for every node in the cells overlapping the box around (x, y) of half-width r.
    template <class Visit>
    void for_each_near(double x, double y, double r, Visit&& visit) const {
      for_each_in_box(x, y, r, r, visit);
    }
    // Calls visit(j) for every node in the cells overlapping the box [x - rx, x + rx] x [y - ry, y + ry].
    template <class Visit>
    void for_each_in_box(double x, double y, double rx, double ry, Visit&& visit) const;
    // As for_each_in_box, or every node of the grid when the box spans more cells than the grid has
    // (a box far wider than the cells: fewer visits than the empty cells' lookups).
    template <class Visit>
    void for_each_in_box_or_all(double x, double y, double rx, double ry, Visit&& visit) const {
      if (nodes.empty()) return;
      const double across = (2.0 * rx * inv_cell + 2.0) * (2.0 * ry * inv_cell_y + 2.0);
      if (across > static_cast<double>(start.size())) {
        for (const std::int32_t j : nodes) visit(j);
        return;
      }
      for_each_in_box(x, y, rx, ry, visit);
    }
  };

  // radius[j] > 0 and finite for every node (the caller checked validity).
  void build(const SimParticles& p, const std::vector<double>& radius);
  int level(std::size_t j) const { return level_[j]; }
  std::size_t levels() const { return exact_.size(); }
  // c_l, the cell size of level l: a node of level l has c_l <= radius < 2 c_l.
  double cell_size(std::size_t l) const { return std::ldexp(r_min_, static_cast<int>(l)); }
  // visit(j) for every node j that may lie within reach(M) of (x, y), where M is the level of the
  // grid searched: l itself for C_l (holding levels <= l), M > l for E_M. reach must be monotone
  // enough for the caller's purpose: a node of level m <= l is found if within reach(l), a node of
  // level M > l if within reach(M).
  template <class Reach, class Visit>
  void for_each_near(double x, double y, std::size_t l, Reach&& reach, Visit&& visit) const {
    cumulative_[l].for_each_near(x, y, reach(l), visit);
    for (std::size_t m = l + 1; m < exact_.size(); ++m)
      if (!exact_[m].empty()) exact_[m].for_each_near(x, y, reach(m), visit);
  }

 private:
  double r_min_ = 0.0;
  std::vector<int> level_;
  std::vector<std::vector<std::int32_t>> members_;  // per level: its nodes, ascending
  std::vector<std::int32_t> cumulative_members_;
  std::vector<Grid> cumulative_, exact_;
};

std::int64_t cell_coord(double v, double inv_cell);

template <class Visit>
void LevelGrids::Grid::for_each_in_box(double x, double y, double rx, double ry, Visit&& visit) const {
  if (nodes.empty()) return;
  const std::int64_t x0 = cell_coord(x - rx, inv_cell), x1 = cell_coord(x + rx, inv_cell);
  const std::int64_t y0 = cell_coord(y - ry, inv_cell_y), y1 = cell_coord(y + ry, inv_cell_y);
  for (std::int64_t cy = y0; cy <= y1; ++cy) {
    for (std::int64_t cx = x0; cx <= x1; ++cx) {
      const int id = find(cx, cy);
      if (id < 0) continue;
      const auto end = start[static_cast<std::size_t>(id) + 1];
      for (auto k = start[static_cast<std::size_t>(id)]; k < end; ++k) visit(nodes[static_cast<std::size_t>(k)]);
    }
  }
}

// The level of a size `ratio` = size / smallest size >= 1: floor(log2(ratio)), exactly (frexp).
int size_level(double ratio);

// Finite position and finite positive spacing; in metric mode finite position and a finite SPD metric
// (q is not read).
bool valid_node(const SimParticles& p, std::size_t i);

// Resets the list for n nodes (padding -1) and the flags, records the first invalid node, and
// fills Boundary nodes' {prev, next}.
void start_list(const SimParticles& p, NeighbourList& list, NeighbourFlags& flags);

// Stores node i's neighbours (sorted ascending by the caller) into the padded list: its count and
// the first list.stride of them. Rows of different nodes can be stored concurrently.
void store_row(std::size_t i, const std::vector<std::int32_t>& found, NeighbourList& list);

// Adds a stored row of `count` neighbours to the flags (largest count, pairs within, overflow).
void add_row_flags(std::int32_t count, const NeighbourList& list, NeighbourFlags& flags);

// store_row, then add_row_flags.
void store_sorted(std::size_t i, const std::vector<std::int32_t>& found, NeighbourList& list, NeighbourFlags& flags);

}  // namespace pdmesh::reference
