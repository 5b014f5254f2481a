// Steps 2 and 3 on the device (mirror of host/sim/reference/forces.cpp, compute_forces): the net
// Lennard-Jones force of eq. 5.11 gathered per node over its padded neighbour row, the tangential
// projection for boundary nodes, and r0 (eq. 5.3). Written for PoCL's CPU device, which vectorizes
// across work-items: every work-item of a group runs the same trip count (the group's largest row,
// shorter rows masked), and the inner loop has one division (1/r^2), one sqrt and no pow/length.
#pragma OPENCL FP_CONTRACT OFF

// The group's largest row length; every work-item must call it (it holds barriers).
int group_loop_count(int count, __local int* scratch) {
  if (get_local_id(0) == 0) *scratch = 0;
  barrier(CLK_LOCAL_MEM_FENCE);
  atomic_max(scratch, count);
  barrier(CLK_LOCAL_MEM_FENCE);
  const int loop = *scratch;
  barrier(CLK_LOCAL_MEM_FENCE);
  return loop;
}

// Net force and r0 of node i. rc2 >= 0: interior rows are a Verlet list and only entries with
// r^2 <= rc2 count (the reference's exact cut-off test); rc2 < 0: every row entry counts.
// Same expressions, in the same order, as the reference, so double results match it bit for bit.
void node_forces(const int i, const int loop_count, const int count, const int base, const REAL xi, const REAL yi,
                 const REAL qi, const uchar kind_i, const REAL rc2, const REAL tx, const REAL ty, const REAL lj_a,
                 const int r0_any_direction, const REAL stability_factor, __global const REAL* x,
                 __global const REAL* y, __global const REAL* q, __global const int* index, REAL* fx_out,
                 REAL* fy_out, REAL* r0_out, REAL* dt2_limit_out, int* coincident_out, int* within_out) {
  const int filter = kind_i == 2 && rc2 >= (REAL)0;
  const REAL four_a = (REAL)-4 * lj_a;
  const REAL four_a_pos = (REAL)4 * lj_a;
  REAL fx = (REAL)0, fy = (REAL)0, stiffness = (REAL)0;
  int coincident = 0, within = 0;
  for (int k = 0; k < loop_count; ++k) {
    const int valid = k < count;
    const int j = valid ? index[base + k] : i;
    const REAL dx = x[j] - xi, dy = y[j] - yi;
    const REAL r2 = dx * dx + dy * dy;
    const int in_range = valid && (!filter || r2 <= rc2);
    within += in_range;
    coincident += in_range && r2 == (REAL)0;
    const int use = in_range && r2 > (REAL)0;
    const REAL inv_r2 = (REAL)1 / (use ? r2 : (REAL)1);
    const REAL inv_r = sqrt(inv_r2);
    const REAL sigma = (REAL)0.5 * (qi + q[j]);
    const REAL s2 = sigma * sigma * inv_r2;
    const REAL s6 = s2 * s2 * s2;
    const REAL f = four_a * sigma * (s6 * s6 - s6) * inv_r;
    fx += use ? f * dx : (REAL)0;
    fy += use ? f * dy : (REAL)0;
    // The stability bound's pair stiffness max(|df/dr|, |f|/r) (reference::lj_pair_stiffness).
    const REAL scale = four_a_pos * sigma * inv_r;
    const REAL radial = fabs(scale * ((REAL)12 * s6 * s6 - (REAL)6 * s6));
    const REAL transverse = fabs(scale * (s6 * s6 - s6));
    stiffness += use ? (radial > transverse ? radial : transverse) : (REAL)0;
  }
  *dt2_limit_out = stability_factor > (REAL)0 && stiffness > (REAL)0 ? (REAL)2 * stability_factor / stiffness : INFINITY;
  if (kind_i == 1) {
    // Boundary nodes slide along their curve: keep the tangential component only.
    const REAL ft = fx * tx + fy * ty;
    fx = ft * tx;
    fy = ft * ty;
  }
  const int any_direction = r0_any_direction && (fx != (REAL)0 || fy != (REAL)0);
  REAL best2 = (REAL)0;
  int found = 0;
  for (int k = 0; k < loop_count; ++k) {
    const int valid = k < count;
    const int j = valid ? index[base + k] : i;
    const REAL dx = x[j] - xi, dy = y[j] - yi;
    const REAL r2 = dx * dx + dy * dy;
    const int ok = valid && (!filter || r2 <= rc2) && r2 > (REAL)0 && (any_direction || fx * dx + fy * dy > (REAL)0);
    const int better = ok && (!found || r2 < best2);
    best2 = better ? r2 : best2;
    found = found || ok;
  }
  *fx_out = fx;
  *fy_out = fy;
  *r0_out = found ? sqrt(best2) : (REAL)0;
  *coincident_out = coincident;
  *within_out = kind_i == 2 ? within : 0;
}

// The StepBackend kernel: forces and r0 of every node over a list that holds exactly the neighbours,
// and the stability bound on dt^2 (INFINITY when off or without stiffness).
__kernel __attribute__((reqd_work_group_size(WG_SIZE, 1, 1)))
void compute_forces(const int n, const int stride, const REAL lj_a, const int r0_any_direction,
                    const REAL stability_factor,
                    __global const REAL* x, __global const REAL* y, __global const REAL* q,
                    __global const uchar* kind, __global const REAL* tx, __global const REAL* ty,
                    __global const int* count, __global const int* index, __global REAL* fx_out,
                    __global REAL* fy_out, __global REAL* r0_out, __global REAL* limit_out,
                    __global int* coincident_out) {
  __local int scratch;
  const int i = get_global_id(0);
  const int active = i < n;
  const uchar kind_i = active ? kind[i] : (uchar)0;
  const int row = active && kind_i != 0 ? min(count[i], stride) : 0;
  const int loop_count = group_loop_count(row, &scratch);
  if (!active) return;
  REAL fx = (REAL)0, fy = (REAL)0, r0 = (REAL)0, limit = INFINITY;
  int coincident = 0, within = 0;
  if (kind_i != 0)
    node_forces(i, loop_count, row, i * stride, x[i], y[i], q[i], kind_i, (REAL)-1, tx[i], ty[i], lj_a,
                r0_any_direction, stability_factor, x, y, q, index, &fx, &fy, &r0, &limit, &coincident, &within);
  limit_out[i] = limit;
  fx_out[i] = fx;
  fy_out[i] = fy;
  r0_out[i] = r0;
  coincident_out[i] = coincident;
}
