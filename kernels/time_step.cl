// Step 4 on the device (mirror of host/sim/reference/time_step.cpp, time_step_and_move): the local
// time step of eqs. 5.8/5.9 and the displacement of eq. 5.6, same expressions as the reference
// (force_norm: reduce.cl).
#pragma OPENCL FP_CONTRACT OFF

// dt_i^2 for a moving node: min(2 r0 / (3 |F|), dt_GM^2), or dt_GM^2 when F = 0 or r0 = 0; then
// capped by the stability bound (INFINITY when off).
REAL local_dt2(const REAL fx, const REAL fy, const REAL r0, const REAL dt_gm2, const REAL stability_limit) {
  const REAL f = force_norm(fx, fy);
  REAL dt2 = dt_gm2;
  if (f > (REAL)0 && r0 > (REAL)0) {  // double: f > 0 exactly when fx^2 + fy^2 > 0
    const REAL limit = (REAL)2 * r0 / ((REAL)3 * f);
    dt2 = dt_gm2 < limit ? dt_gm2 : limit;
  }
  return stability_limit < dt2 ? stability_limit : dt2;
}

__kernel __attribute__((reqd_work_group_size(WG_SIZE, 1, 1))) void time_step_and_move(
    const int n, const REAL dt_gm2, const int has_limit, __global const uchar* kind, __global const REAL* fx,
    __global const REAL* fy, __global const REAL* r0, __global const REAL* dt2_limit, __global REAL* dx_out,
    __global REAL* dy_out, __global REAL* dt2_out) {
  const int i = get_global_id(0);
  if (i >= n) return;
  if (kind[i] == 0) {
    dx_out[i] = (REAL)0;
    dy_out[i] = (REAL)0;
    dt2_out[i] = (REAL)0;
    return;
  }
  const REAL dt2 = local_dt2(fx[i], fy[i], r0[i], dt_gm2, has_limit ? dt2_limit[i] : INFINITY);
  dt2_out[i] = dt2;
  dx_out[i] = REAL_C(0.5) * dt2 * fx[i];
  dy_out[i] = REAL_C(0.5) * dt2 * fy[i];
}

// The carried move turned towards the force (host/sim/reference/time_step.cpp, momentum_steer: the same
// expressions in the same order): p = (1 - mix) p + mix |p| F / |F|; unchanged where p = 0 or F = 0.
REAL2 momentum_steer(const REAL2 p, const REAL mix, const REAL fx, const REAL fy) {
  const REAL pl = force_norm(p.x, p.y);  // double: sqrt(x^2 + y^2), the reference's
  const REAL fl = force_norm(fx, fy);
  if (!(pl > (REAL)0) || !(fl > (REAL)0)) return p;
  return (REAL2)(((REAL)1 - mix) * p.x + mix * pl * fx / fl, ((REAL)1 - mix) * p.y + mix * pl * fy / fl);
}

// Heavy-ball momentum for one node (host/sim/reference/time_step.cpp, momentum_move: the same
// expressions in the same order): p steered (mix > 0); d = g + beta p; g where d points against F; |d|
// capped to r0 / 3.
REAL2 momentum_move(const REAL gx, const REAL gy, const REAL2 carried, const REAL beta, const REAL mix, const REAL fx,
                    const REAL fy, const REAL r0) {
  const REAL2 p = mix > (REAL)0 ? momentum_steer(carried, mix, fx, fy) : carried;
  REAL dx = gx + beta * p.x;
  REAL dy = gy + beta * p.y;
  if (dx * fx + dy * fy < (REAL)0) {
    dx = gx;
    dy = gy;
  }
  if (r0 > (REAL)0) {
    const REAL cap = r0 / (REAL)3;
    const REAL len = force_norm(dx, dy);  // double: sqrt(dx^2 + dy^2), the reference's
    if (len > cap) {
      const REAL s = cap / len;
      dx = dx * s;
      dy = dy * s;
    }
  }
  return (REAL2)(dx, dy);
}

// StepBackend::apply_momentum: moves (dx, dy) in = g, out = d; carried (x and y interleaved) in = p,
// out = d. Fixed nodes: d = p = 0.
__kernel __attribute__((reqd_work_group_size(WG_SIZE, 1, 1))) void apply_momentum(
    const int n, const REAL beta, const REAL mix, __global const uchar* kind, __global const REAL* fx,
    __global const REAL* fy, __global const REAL* r0, __global REAL* dx, __global REAL* dy, __global REAL2* carried) {
  const int i = get_global_id(0);
  if (i >= n) return;
  if (kind[i] == 0) {
    carried[i] = (REAL2)((REAL)0, (REAL)0);
    return;
  }
  const REAL2 d = momentum_move(dx[i], dy[i], carried[i], beta, mix, fx[i], fy[i], r0[i]);
  dx[i] = d.x;
  dy[i] = d.y;
  carried[i] = d;
}

#if PDMESH_FORCE_LOOP_VECTOR
// The same rules on eight nodes at once (device_step's CPU shape, step_moves8): each lane computes the
// scalar functions' expressions in the same order, and a select takes the branch the scalar code would
// take, so every lane is bit for bit the scalar result. PoCL's CPU device runs a work-group's
// work-items one after the other in scalar code; a node's local time step and momentum hold five
// square roots and divisions, which here run in vector instructions, eight nodes per instruction.

// force_norm of each lane.
REAL8 force_norm8(const REAL8 fx, const REAL8 fy) {
#if PDMESH_DOUBLE
  return sqrt(fx * fx + fy * fy);
#else
  const REAL8 sx = fx * 0x1p-64f, sy = fy * 0x1p-64f;
  return select(sqrt(fx * fx + fy * fy), sqrt(sx * sx + sy * sy) * 0x1p64f, fmax(fabs(fx), fabs(fy)) > (REAL8)0x1p60f);
#endif
}

// local_dt2 of each lane, given its |F| f = force_norm8(fx, fy).
REAL8 local_dt2_8(const REAL8 f, const REAL8 r0, const REAL dt_gm2, const REAL8 stability_limit) {
  const REAL8 gm2 = (REAL8)(dt_gm2);
  const REAL8 limit = (REAL)2 * r0 / ((REAL)3 * f);
  const REAL8 capped = select(limit, gm2, gm2 < limit);
  const REAL8 dt2 = select(gm2, capped, (f > (REAL)0) & (r0 > (REAL)0));
  return select(dt2, stability_limit, stability_limit < dt2);
}

// momentum_move of each lane (momentum_steer inlined): the carried move (px, py) steered when mix > 0,
// d = g + beta p, g where d points against F, |d| capped to r0 / 3.
void momentum_move8(const REAL8 gx, const REAL8 gy, REAL8 px, REAL8 py, const REAL beta, const REAL mix, const REAL8 fx,
                    const REAL8 fy, const REAL8 r0, REAL8* dx_out, REAL8* dy_out) {
  if (mix > (REAL)0) {
    const REAL8 pl = force_norm8(px, py);
    const REAL8 fl = force_norm8(fx, fy);
    const REAL8 sx = ((REAL)1 - mix) * px + mix * pl * fx / fl, sy = ((REAL)1 - mix) * py + mix * pl * fy / fl;
    const MASK8 steer = (pl > (REAL)0) & (fl > (REAL)0);
    px = select(px, sx, steer);
    py = select(py, sy, steer);
  }
  const REAL8 hx = gx + beta * px, hy = gy + beta * py;
  const MASK8 back = hx * fx + hy * fy < (REAL)0;
  const REAL8 dx = select(hx, gx, back), dy = select(hy, gy, back);
  const REAL8 cap = r0 / (REAL)3;
  const REAL8 len = force_norm8(dx, dy);
  const REAL8 s = cap / len;
  const MASK8 clip = (r0 > (REAL)0) & (len > cap);
  *dx_out = select(dx, dx * s, clip);
  *dy_out = select(dy, dy * s, clip);
}
#endif
