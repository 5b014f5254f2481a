// The pair-force floor on the device (host/opencl/device_floor.hpp): the floor iteration of
// host/sim/pair_floor.hpp, one work-item per node of the lattice sorted by cells. Node i finds its
// cell from its position as bin_floor_points binned it (in double the same cell; in float a node
// within a rounding of a cell edge may take the neighbouring cell), tests every candidate of its 3 x 3
// cells (three contiguous runs of the sorted arrays) against its cut-off, sums eq. 5.11 with sigma the
// pair's mean q over the pairs within it, and writes x + dt^2/2 F to a second array. The expressions
// and the summation order are those of floor_rows_scalar (sim/pair_floor_kernel.hpp): each run summed
// from zero, then added to the node's force; so in double the new positions agree with it bit for bit.
#pragma OPENCL FP_CONTRACT OFF

__kernel __attribute__((reqd_work_group_size(WG_SIZE, 1, 1))) void pair_floor(
    const int n, const int cells_x, const int cells_y, const REAL x0, const REAL y0, const REAL cell, const REAL cutoff,
    const REAL minus_four_a, const REAL half_dt2, __global const REAL* x, __global const REAL* y,
    __global const REAL* q, __global const uint* cell_start, __global REAL* new_x, __global REAL* new_y) {
  const int i = get_global_id(0);
  if (i >= n) return;
  const REAL xi = x[i], yi = y[i], qi = q[i];
  const int cx = min(cells_x - 1, (int)((xi - x0) / cell));
  const int cy = min(cells_y - 1, (int)((yi - y0) / cell));
  const int c_lo = max(cx - 1, 0), c_hi = min(cx + 1, cells_x - 1);
  const int r_lo = max(cy - 1, 0), r_hi = min(cy + 1, cells_y - 1);
  const REAL rc = cutoff * qi;
  const REAL rc2 = rc * rc;
  REAL fx_total = REAL_C(0.0), fy_total = REAL_C(0.0);
  for (int r = r_lo; r <= r_hi; ++r) {
    const uint b = cell_start[r * cells_x + c_lo], e = cell_start[r * cells_x + c_hi + 1];
    REAL fx = REAL_C(0.0), fy = REAL_C(0.0);
    for (uint k = b; k < e; ++k) {
      const REAL dx = x[k] - xi, dy = y[k] - yi;
      const REAL r2 = dx * dx + dy * dy;
      if (!(r2 <= rc2 && r2 > REAL_C(0.0))) continue;
      const REAL inv_r2 = REAL_C(1.0) / r2;
      const REAL inv_r = sqrt(inv_r2);
      const REAL sigma = REAL_C(0.5) * (qi + q[k]);
      const REAL s2 = sigma * sigma * inv_r2;
      const REAL s6 = s2 * s2 * s2;
      const REAL f = minus_four_a * sigma * (s6 * s6 - s6) * inv_r;
      fx += f * dx;
      fy += f * dy;
    }
    fx_total += fx;
    fy_total += fy;
  }
  new_x[i] = xi + half_dt2 * fx_total;
  new_y[i] = yi + half_dt2 * fy_total;
}
