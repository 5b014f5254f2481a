// One whole iteration for the device-resident run (host/opencl/device_simulation.cpp) in one launch:
// forces + r0 (forces.cl), local time step + move (time_step.cl), spacing update (spacing_field.cl),
// the domain-tag filter that picks the few interior nodes the host must test exactly, the Verlet-skin
// displacement check, and per-group partial sums (reduce.cl). A second, small kernel writes back
// the positions the host's boundary handling decided.
#pragma OPENCL FP_CONTRACT OFF

#define STEP_PARTIALS 7  // sum |F|, sum kinetic, moving, pairs within, coincident | max |F|, max skin use

// The background field's arrays, passed as one group of arguments.
#define BG_ARGS                                                                                      \
  const REAL bg_origin_x, const REAL bg_origin_y, const REAL bg_inv_root, const int bg_grid,          \
      __global const int *bg_root, __global const int *bg_child, __global const int *bg_corner,      \
      __global const int *bg_tag, __global const REAL *bg_q
#define BG_TAG(px, py) domain_tag_at(px, py, bg_origin_x, bg_origin_y, bg_inv_root, bg_grid, bg_root, bg_child, bg_tag)

// Spacing and domain tag at (px, py) from one descent: spacing_at's expression, domain_tag_at's tag.
REAL bg_spacing_and_tag(const REAL px, const REAL py, int* tag_out, BG_ARGS) {
  REAL u, v;
  const int leaf = bg_locate(px, py, bg_origin_x, bg_origin_y, bg_inv_root, bg_grid, bg_root, bg_child, &u, &v);
  *tag_out = bg_tag[leaf];
  const REAL q00 = bg_q[bg_corner[4 * leaf + 0]];
  const REAL q10 = bg_q[bg_corner[4 * leaf + 1]];
  const REAL q01 = bg_q[bg_corner[4 * leaf + 2]];
  const REAL q11 = bg_q[bg_corner[4 * leaf + 3]];
  return ((REAL)1 - v) * (((REAL)1 - u) * q00 + u * q10) + v * (((REAL)1 - u) * q01 + u * q11);
}
#define BG_PASS bg_origin_x, bg_origin_y, bg_inv_root, bg_grid, bg_root, bg_child, bg_corner, bg_tag, bg_q

// Inputs x, y, q (current), outputs x_next, y_next, q_next. tag[i]: the domain tag of node i's current
// position (updated here for the next iteration). Interior nodes whose move starts, ends or has its
// midpoint in a leaf that is not surely inside are appended to cand_index / cand_rec (x, y, dx, dy)
// with an integer atomic counter (counters[0]); boundary nodes write (x, y, dx, dy) to their slot
// bslot[i] of brec. skin_use: (|x_next - x_build| + cutoff max(0, q_next - q_build)) / (skin cutoff
// q_build), maximised per group (interior nodes the host does not touch; the host covers the rest).
__kernel __attribute__((reqd_work_group_size(WG_SIZE, 1, 1)))
void device_step(const int n, const int stride, const REAL cutoff, const REAL lj_a, const int r0_any_direction,
                 const REAL stability_factor, const REAL dt_gm2, const REAL skin_cutoff, __global const REAL* x, __global const REAL* y,
                 __global const REAL* q, __global const uchar* kind, __global const REAL* tx,
                 __global const REAL* ty, __global const int* count, __global const int* index,
                 __global const REAL* x_build, __global const REAL* y_build, __global const REAL* q_build,
                 __global const int* bslot, __global REAL* x_next, __global REAL* y_next, __global REAL* q_next,
                 __global uchar* tag, __global REAL* brec, __global int* cand_index, __global REAL* cand_rec,
                 __global int* counters, __global REAL* partials, BG_ARGS) {
  __local int scratch;
  __local REAL values[STEP_PARTIALS * WG_SIZE];
  const int i = get_global_id(0), l = get_local_id(0);
  const int active = i < n;
  const uchar kind_i = active ? kind[i] : (uchar)0;
  const int row = active && kind_i != 0 ? min(count[i], stride) : 0;
  const int loop_count = group_loop_count(row, &scratch);
  REAL f = (REAL)0, kinetic = (REAL)0, skin_use = (REAL)0;
  int within = 0, coincident = 0;
  if (active) {
    const REAL xi = x[i], yi = y[i], qi = q[i];
    REAL dx = (REAL)0, dy = (REAL)0;
    if (kind_i != 0) {
      REAL fx, fy, r0, limit;
      const REAL rc = cutoff * qi;
      node_forces(i, loop_count, row, i * stride, xi, yi, qi, kind_i, rc * rc, tx[i], ty[i], lj_a, r0_any_direction,
                  stability_factor, x, y, q, index, &fx, &fy, &r0, &limit, &coincident, &within);
      const REAL dt2 = local_dt2(fx, fy, r0, dt_gm2, limit);
      dx = (REAL)0.5 * dt2 * fx;
      dy = (REAL)0.5 * dt2 * fy;
      const REAL f2 = fx * fx + fy * fy;
      f = sqrt(f2);
      kinetic = (REAL)0.125 * dt2 * f2;
    }
    const REAL xn = xi + dx, yn = yi + dy;
    int tag_to;
    const REAL qn = bg_spacing_and_tag(xn, yn, &tag_to, BG_PASS);
    int host = 0;
    if (kind_i == 1) {
      const int s = bslot[i];
      brec[4 * s] = xi;
      brec[4 * s + 1] = yi;
      brec[4 * s + 2] = dx;
      brec[4 * s + 3] = dy;
      host = 1;
    } else if (kind_i == 2) {
      const REAL xm = xi + (REAL)0.5 * dx, ym = yi + (REAL)0.5 * dy;
      // The midpoint only matters when both ends are surely inside.
      if (tag[i] != 0 || tag_to != 0 || BG_TAG(xm, ym) != 0 || !isfinite(xn) || !isfinite(yn)) {
        const int s = atomic_inc(&counters[0]);
        cand_index[s] = i;
        cand_rec[4 * s] = xi;
        cand_rec[4 * s + 1] = yi;
        cand_rec[4 * s + 2] = dx;
        cand_rec[4 * s + 3] = dy;
        host = 1;
      }
      tag[i] = (uchar)tag_to;
    }
    x_next[i] = xn;
    y_next[i] = yn;
    q_next[i] = qn;
    if (!host && kind_i == 2) {
      const REAL ex = xn - x_build[i], ey = yn - y_build[i];
      const REAL grow = qn > q_build[i] ? cutoff * (qn - q_build[i]) : (REAL)0;
      skin_use = (sqrt(ex * ex + ey * ey) + grow) / (skin_cutoff * q_build[i]);
    }
  }
  const int moving = active && kind_i != 0;
  values[l] = f;
  values[WG_SIZE + l] = kinetic;
  values[2 * WG_SIZE + l] = moving ? (REAL)1 : (REAL)0;
  values[3 * WG_SIZE + l] = (REAL)within;
  values[4 * WG_SIZE + l] = (REAL)coincident;
  values[5 * WG_SIZE + l] = f;
  values[6 * WG_SIZE + l] = skin_use;
  group_reduce(values, STEP_PARTIALS, 5);
  if (l < STEP_PARTIALS) partials[STEP_PARTIALS * get_group_id(0) + l] = values[l * WG_SIZE];
}

// Writes back the m positions the host decided (boundary nodes re-snapped, candidates moved or
// snapped): rec = (x, y, tx, ty) per entry; recomputes q there and the domain tag.
__kernel __attribute__((reqd_work_group_size(WG_SIZE, 1, 1)))
void apply_host_moves(const int m, __global const int* rec_index, __global const REAL* rec, __global REAL* x,
                      __global REAL* y, __global REAL* q, __global REAL* tx, __global REAL* ty, __global uchar* tag,
                      BG_ARGS) {
  const int k = get_global_id(0);
  if (k >= m) return;
  const int i = rec_index[k];
  const REAL px = rec[4 * k], py = rec[4 * k + 1];
  x[i] = px;
  y[i] = py;
  tx[i] = rec[4 * k + 2];
  ty[i] = rec[4 * k + 3];
  int t;
  q[i] = bg_spacing_and_tag(px, py, &t, BG_PASS);
  tag[i] = (uchar)t;
}
