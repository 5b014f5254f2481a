// The multi-level hashed cell grids of host/sim/reference/binning.cpp in flat arrays, built on the host
// in O(N): the oracle of the device's binning (kernels/binning.cl, tests/test_device_neighbours.cpp),
// which bins on the device, so that a rebuild downloads no positions.
#pragma once
#include <cstdint>
#include <vector>

#include "sim/cell_hash.hpp"

namespace pdmesh::ocl {

// Grid g = 2L is the cumulative grid C_L (nodes of level <= L), g = 2L + 1 the exact grid E_L (level L
// only); an absent grid (no node of level L) has inv_cell 0. Cell size of level L: R_min 2^L with
// R = radius_factor * q and level(j) = floor(log2(R_j / R_min)), exactly as the reference.
struct NeighbourGrids {
  int levels = 0;
  std::vector<std::int32_t> level;         // per node
  std::vector<double> inv_cell;            // per grid
  std::vector<std::int32_t> table_offset;  // per grid: first slot in table_*
  std::vector<std::int32_t> table_mask;    // per grid: capacity - 1 (capacity a power of two)
  std::vector<std::int32_t> start_offset;  // per grid: first entry in cell_start
  std::vector<std::int32_t> nodes_offset;  // per grid: first entry in cell_nodes
  std::vector<std::int64_t> table_cx, table_cy;
  std::vector<std::int32_t> table_id;    // -1 = empty slot; else the dense cell id within its grid
  std::vector<std::int32_t> cell_start;  // per grid: cells + 1 prefix offsets
  std::vector<std::int32_t> cell_nodes;  // per grid: nodes grouped by cell, ascending within a cell

  std::size_t bytes() const;
};

// Builds the grids over all n nodes (positions and spacings must be finite, q > 0: the caller checks).
// Nodes of every kind are binned (interior nodes find neighbours of any kind).
void build_neighbour_grids(const double* x, const double* y, const double* q, std::size_t n, double radius_factor,
                           NeighbourGrids& grids);

// The hash of a cell (sim/cell_hash.hpp), which the kernel's nb_hash repeats.
using pdmesh::cell_hash;

// The device's bucket of cell (cx, cy) in a grid of mask + 1 buckets (kernels/binning.cl, nb_bucket): the
// hash of the cell's 4x4 block, shifted, with the cell's place in its block in the low 4 bits, so a
// block's cells take consecutive buckets.
inline std::uint64_t grid_bucket(std::int64_t cx, std::int64_t cy, std::uint64_t mask) {
  const auto ux = static_cast<std::uint64_t>(cx), uy = static_cast<std::uint64_t>(cy);
  return ((cell_hash(static_cast<std::int64_t>(ux >> 2), static_cast<std::int64_t>(uy >> 2)) << 4) | ((uy & 3) << 2) |
          (ux & 3)) &
         mask;
}

}  // namespace pdmesh::ocl
