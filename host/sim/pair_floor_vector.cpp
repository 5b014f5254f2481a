// The pair-force floor's vector loop: sim/pair_floor_kernel.hpp with an OpenMP SIMD candidate loop
// (-fopenmp-simd; -fno-math-errno and -fno-trapping-math let GCC vectorize the square root and turn
// the cut-off test into a select on AVX2: set for this file in CMakeLists.txt). With GCC on x86-64
// the function is cloned for x86-64-v4 (AVX-512), x86-64-v3 (AVX2, FMA) and the baseline, and the
// loader picks the best the CPU has: what -march=native would give, in a binary that still runs on
// any x86-64. Other compilers and sanitizer builds get the baseline alone.
#define PDMESH_FLOOR_SIMD _Pragma("omp simd reduction(+ : fx, fy)")
#define PDMESH_FLOOR_SKIP 0
#include "sim/pair_floor_kernel.hpp"

#include <string>

#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && !defined(__SANITIZE_ADDRESS__)
#define PDMESH_FLOOR_CLONES 1
#define PDMESH_FLOOR_TARGETS __attribute__((target_clones("arch=x86-64-v4", "arch=x86-64-v3", "default")))
#else
#define PDMESH_FLOOR_CLONES 0
#define PDMESH_FLOOR_TARGETS
#endif

namespace pdmesh {

PDMESH_FLOOR_TARGETS
void floor_rows_vector(const FloorLattice& lattice, std::size_t row_begin, std::size_t row_end, double dt2,
                       double* new_x, double* new_y) {
  floor_rows(lattice, row_begin, row_end, dt2, new_x, new_y);
}

std::string floor_vector_isa() {
#if PDMESH_FLOOR_CLONES
  // The clones' order of preference, as the loader's resolver takes them.
  if (__builtin_cpu_supports("x86-64-v4")) return "x86-64-v4 (AVX-512)";
  if (__builtin_cpu_supports("x86-64-v3")) return "x86-64-v3 (AVX2)";
  return "x86-64 (SSE2)";
#else
  return "baseline (no clones in this build)";
#endif
}

}  // namespace pdmesh
