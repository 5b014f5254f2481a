// The pair-force floor's scalar loop: sim/pair_floor_kernel.hpp compiled with the vectorizer off
// (-fno-tree-vectorize -fno-tree-slp-vectorize, set for this file in CMakeLists.txt), pairs beyond the
// cut-off skipped by a branch.
#define PDMESH_FLOOR_SIMD
#define PDMESH_FLOOR_SKIP 1
#include "sim/pair_floor_kernel.hpp"

namespace pdmesh {

void floor_rows_scalar(const FloorLattice& lattice, std::size_t row_begin, std::size_t row_end, double dt2,
                       double* new_x, double* new_y) {
  floor_rows(lattice, row_begin, row_end, dt2, new_x, new_y);
}

}  // namespace pdmesh
