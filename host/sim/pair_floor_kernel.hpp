// The pair-force floor's loop (sim/pair_floor.hpp), written once and compiled twice with different
// flags: sim/pair_floor_scalar.cpp with the vectorizer off, sim/pair_floor_vector.cpp with OpenMP SIMD.
// The including file defines PDMESH_FLOOR_SIMD, the pragma of the candidate loop (empty: none), and
// PDMESH_FLOOR_SKIP: 1 to skip the pairs beyond the cut-off by a branch (the faster scalar form: about
// a fifth of the candidates are within it), 0 to compute every candidate and select (one path, which
// vectorizes).
// Internal linkage (an unnamed namespace in a header, on purpose): each file keeps its own copy,
// compiled with its own flags, which the linker may not merge.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>

#include "sim/pair_floor.hpp"

#if !defined(PDMESH_FLOOR_SIMD) || !defined(PDMESH_FLOOR_SKIP)
#error "PDMESH_FLOOR_SIMD and PDMESH_FLOOR_SKIP must be defined before this header"
#endif

namespace pdmesh {
namespace {

// The force on a node at (xi, yi) of spacing qi from the candidates [b, e): pairs within rc2 (and not
// the node itself, r^2 = 0) get eq. 5.11 with sigma the pair's mean q, the kernel's expressions.
[[gnu::always_inline]] inline void floor_candidates(const double* x, const double* y, const double* q, std::uint32_t b,
                                                    std::uint32_t e, double xi, double yi, double qi, double rc2,
                                                    double minus_four_a, double& fx_out, double& fy_out) {
  double fx = 0.0, fy = 0.0;
  const double *xs = x + b, *ys = y + b, *qs = q + b;
  const std::ptrdiff_t n = static_cast<std::ptrdiff_t>(e) - static_cast<std::ptrdiff_t>(b);
  PDMESH_FLOOR_SIMD
  for (std::ptrdiff_t k = 0; k < n; ++k) {
    const double dx = xs[k] - xi, dy = ys[k] - yi;
    const double r2 = dx * dx + dy * dy;
    const bool in = (r2 <= rc2) & (r2 > 0.0);
    if (PDMESH_FLOOR_SKIP && !in) continue;
    const double inv_r2 = 1.0 / (in ? r2 : 1.0);
    const double inv_r = std::sqrt(inv_r2);
    const double sigma = 0.5 * (qi + qs[k]);
    const double s2 = sigma * sigma * inv_r2;
    const double s6 = s2 * s2 * s2;
    const double f = minus_four_a * sigma * (s6 * s6 - s6) * inv_r;
    fx += in ? f * dx : 0.0;
    fy += in ? f * dy : 0.0;
  }
  fx_out += fx;
  fy_out += fy;
}

// Cell rows [row_begin, row_end): every node's force over its 3 x 3 cells (three runs of the sorted
// arrays, one per neighbouring cell row) and its move into (new_x, new_y).
[[gnu::always_inline]] inline void floor_rows(const FloorLattice& lattice, std::size_t row_begin, std::size_t row_end,
                                              double dt2, double* new_x, double* new_y) {
  const double* x = lattice.x.data();
  const double* y = lattice.y.data();
  const double* q = lattice.q.data();
  const std::uint32_t* start = lattice.cell_start.data();
  const std::size_t w = lattice.cells_x, h = lattice.cells_y;
  const double minus_four_a = -4.0 * lattice.lj_a, half_dt2 = 0.5 * dt2;
  for (std::size_t cy = row_begin; cy < row_end; ++cy) {
    const std::size_t r_lo = cy > 0 ? cy - 1 : 0, r_hi = std::min(cy + 1, h - 1);
    for (std::size_t cx = 0; cx < w; ++cx) {
      const std::uint32_t ib = start[cy * w + cx], ie = start[cy * w + cx + 1];
      if (ib == ie) continue;
      const std::size_t c_lo = cx > 0 ? cx - 1 : 0, c_hi = std::min(cx + 1, w - 1);
      std::uint32_t run_b[3], run_e[3];
      std::size_t runs = 0;
      for (std::size_t r = r_lo; r <= r_hi; ++r, ++runs) {
        run_b[runs] = start[r * w + c_lo];
        run_e[runs] = start[r * w + c_hi + 1];
      }
      for (std::uint32_t i = ib; i < ie; ++i) {
        const double xi = x[i], yi = y[i], qi = q[i];
        const double rc = lattice.cutoff * qi;
        double fx = 0.0, fy = 0.0;
        for (std::size_t k = 0; k < runs; ++k)
          floor_candidates(x, y, q, run_b[k], run_e[k], xi, yi, qi, rc * rc, minus_four_a, fx, fy);
        new_x[i] = xi + half_dt2 * fx;
        new_y[i] = yi + half_dt2 * fy;
      }
    }
  }
}

}  // namespace
}  // namespace pdmesh
