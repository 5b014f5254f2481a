// Metric mode on the device (mirror of host/sim/reference/forces_metric.cpp, time_step.cpp and
// metric_pair.hpp): particles as ellipses, each node with its metric M = [[m11, m12], [m12, m22]].
// A pair is measured in the geometric mean of the two nodes' metrics; the force is eq. 5.11
// with sigma = 1 at the pair's metric distance rho, along d; r0 is the smallest rho in the half-plane
// of F measured in the pair's metric, and |F| is measured in the node's metric. The same expressions
// in the same order as the reference, one neighbour at a time in list order, so double results agree
// with it bit for bit (no contraction). The neighbour rows come from the StepBackend's list.
#pragma OPENCL FP_CONTRACT OFF

// A node's pair factor (N = M / sqrt(det M) as [[a, b], [b, c]], w = (det M)^(1/4)) as (a, b, c, w).
#if PDMESH_DOUBLE
#define REAL4 double4
#else
#define REAL4 float4
#endif

// reference::pair_factor.
REAL4 metric_pair_factor(const REAL m11, const REAL m12, const REAL m22) {
  const REAL s = sqrt(m11 * m22 - m12 * m12);
  const REAL inv = (REAL)1 / s;
  return (REAL4)(m11 * inv, m12 * inv, m22 * inv, sqrt(s));
}

// rho^2 = d^T (M_i # M_j) d = w_i w_j (d^T G d) / sqrt(det G), G = N_i + N_j (reference::pair_distance2).
REAL metric_pair_distance2(const REAL4 si, const REAL4 sj, const REAL dx, const REAL dy) {
  const REAL a = si.x + sj.x, b = si.y + sj.y, c = si.z + sj.z;
  const REAL dgd = a * dx * dx + (REAL)2 * b * dx * dy + c * dy * dy;
  return si.w * sj.w * dgd / sqrt(a * c - b * b);
}

// The sign of f^T G d (reference::pair_metric_dot_sign).
REAL metric_pair_dot_sign(const REAL4 si, const REAL4 sj, const REAL fx, const REAL fy, const REAL dx, const REAL dy) {
  const REAL a = si.x + sj.x, b = si.y + sj.y, c = si.z + sj.z;
  return (a * fx + b * fy) * dx + (b * fx + c * fy) * dy;
}

// v^T M v (reference::metric_norm2).
REAL metric_norm2(const REAL m11, const REAL m12, const REAL m22, const REAL vx, const REAL vy) {
  return m11 * vx * vx + (REAL)2 * m12 * vx * vy + m22 * vy * vy;
}

// |F|_M = sqrt(F^T M F). Double: that expression (the reference's). Float: F^T M F overflows for a
// crowded pair in a fine metric (|F| ~ 1e16 with M ~ 1e6), which would stop the node for that step;
// there F is scaled by the exact power of two 2^-64 first and the root scaled back (reduce.cl's
// force_norm does the same for |F|).
REAL metric_force_norm(const REAL m11, const REAL m12, const REAL m22, const REAL fx, const REAL fy) {
#if PDMESH_DOUBLE
  return sqrt(metric_norm2(m11, m12, m22, fx, fy));
#else
  const float f2 = metric_norm2(m11, m12, m22, fx, fy);
  if (isinf(f2)) return sqrt(metric_norm2(m11, m12, m22, fx * 0x1p-64f, fy * 0x1p-64f)) * 0x1p64f;
  return sqrt(f2);
#endif
}

REAL4 node_pair_factor(const int j, __global const REAL* m11, __global const REAL* m12, __global const REAL* m22) {
  return metric_pair_factor(m11[j], m12[j], m22[j]);
}

// StepBackend::compute_forces in metric mode (reference::compute_forces_metric).
__kernel __attribute__((reqd_work_group_size(WG_SIZE, 1, 1))) void compute_forces_metric(
    const int n, const int stride, const REAL lj_a, const int r0_any_direction, const REAL stability_factor,
    __global const REAL2* xy, __global const REAL* m11, __global const REAL* m12, __global const REAL* m22,
    __global const uchar* kind, __global const REAL* tx, __global const REAL* ty, __global const int* count,
    __global const int* index, __global REAL* fx_out, __global REAL* fy_out, __global REAL* r0_out,
    __global REAL* limit_out, __global int* coincident_out) {
  const int i = get_global_id(0);
  if (i >= n) return;
  const int kind_i = (int)kind[i];
  if (kind_i == 0) {
    fx_out[i] = (REAL)0;
    fy_out[i] = (REAL)0;
    r0_out[i] = (REAL)0;
    limit_out[i] = INFINITY;
    coincident_out[i] = 0;
    return;
  }
  const int row = min(count[i], stride);
  const long base = row_base(i, stride);
  const REAL2 pi = xy[i];
  const REAL4 si = node_pair_factor(i, m11, m12, m22);
  const REAL four_a = (REAL)-4 * lj_a, four_a_pos = (REAL)4 * lj_a;
  REAL fx = (REAL)0, fy = (REAL)0, stiffness = (REAL)0;
  int coincident = 0;
  for (int k = 0; k < row; ++k) {
    const int j = index[base + k];
    const REAL2 pj = xy[j];
    const REAL dx = pj.x - pi.x, dy = pj.y - pi.y;
    const REAL rho2 = metric_pair_distance2(si, node_pair_factor(j, m11, m12, m22), dx, dy);
    if (rho2 == (REAL)0) {
      ++coincident;
      continue;
    }
    const REAL inv_rho2 = (REAL)1 / rho2;
    const REAL inv_rho = sqrt(inv_rho2);
    // reference::lj_pair_magnitude(1, inv_rho2, a) * inv_rho: sigma = 1 in the pair's metric.
    const REAL s6 = inv_rho2 * inv_rho2 * inv_rho2;
    const REAL f = four_a * (REAL)1 * (s6 * s6 - s6) * inv_rho;
    fx += f * dx;
    fy += f * dy;
    const REAL scale = four_a_pos * (REAL)1 * inv_rho;
    const REAL radial = fabs(scale * ((REAL)12 * s6 * s6 - (REAL)6 * s6));
    const REAL transverse = fabs(scale * (s6 * s6 - s6));
    stiffness += radial > transverse ? radial : transverse;
  }
  limit_out[i] = stability_factor > (REAL)0 && stiffness > (REAL)0 ? (REAL)2 * stability_factor / stiffness : INFINITY;
  if (kind_i == 1) {
    const REAL ft = fx * tx[i] + fy * ty[i];
    fx = ft * tx[i];
    fy = ft * ty[i];
  }
  const int any_direction = r0_any_direction && (fx != (REAL)0 || fy != (REAL)0);
  REAL best2 = INFINITY;
  int found = 0;
  for (int k = 0; k < row; ++k) {
    const int j = index[base + k];
    const REAL2 pj = xy[j];
    const REAL dx = pj.x - pi.x, dy = pj.y - pi.y;
    const REAL4 sj = node_pair_factor(j, m11, m12, m22);
    const REAL rho2 = metric_pair_distance2(si, sj, dx, dy);
    if (rho2 > (REAL)0 && rho2 < best2 && (any_direction || metric_pair_dot_sign(si, sj, fx, fy, dx, dy) > (REAL)0)) {
      best2 = rho2;
      found = 1;
    }
  }
  fx_out[i] = fx;
  fy_out[i] = fy;
  r0_out[i] = found ? sqrt(best2) : (REAL)0;
  coincident_out[i] = coincident;
}

// StepBackend::time_step_and_move in metric mode: dt^2 = min(2 r0 / (3 |F|_M), dt_GM^2), capped by the
// stability bound (INFINITY when off); Fixed nodes: 0.
__kernel __attribute__((reqd_work_group_size(WG_SIZE, 1, 1))) void time_step_and_move_metric(
    const int n, const REAL dt_gm2, const int has_limit, __global const uchar* kind, __global const REAL* fx,
    __global const REAL* fy, __global const REAL* r0, __global const REAL* dt2_limit, __global const REAL* m11,
    __global const REAL* m12, __global const REAL* m22, __global REAL* dx_out, __global REAL* dy_out,
    __global REAL* dt2_out) {
  const int i = get_global_id(0);
  if (i >= n) return;
  if (kind[i] == 0) {
    dx_out[i] = (REAL)0;
    dy_out[i] = (REAL)0;
    dt2_out[i] = (REAL)0;
    return;
  }
  const REAL f = metric_force_norm(m11[i], m12[i], m22[i], fx[i], fy[i]);
  REAL dt2 = dt_gm2;
  if (f > (REAL)0 && r0[i] > (REAL)0) {  // double: f > 0 exactly when F^T M F > 0
    const REAL limit = (REAL)2 * r0[i] / ((REAL)3 * f);
    dt2 = limit < dt_gm2 ? limit : dt_gm2;
  }
  if (has_limit) dt2 = dt2_limit[i] < dt2 ? dt2_limit[i] : dt2;
  dt2_out[i] = dt2;
  dx_out[i] = REAL_C(0.5) * dt2 * fx[i];
  dy_out[i] = REAL_C(0.5) * dt2 * fy[i];
}

// StepBackend::apply_momentum in metric mode (reference::momentum_move_metric): the cap |d|_M <= r0 / 3.
__kernel __attribute__((reqd_work_group_size(WG_SIZE, 1, 1))) void apply_momentum_metric(
    const int n, const REAL beta, const REAL mix, __global const uchar* kind, __global const REAL* fx,
    __global const REAL* fy, __global const REAL* r0, __global const REAL* m11, __global const REAL* m12,
    __global const REAL* m22, __global REAL* dx_io, __global REAL* dy_io, __global REAL2* carried) {
  const int i = get_global_id(0);
  if (i >= n) return;
  if (kind[i] == 0) {
    carried[i] = (REAL2)((REAL)0, (REAL)0);
    return;
  }
  const REAL gx = dx_io[i], gy = dy_io[i];
  const REAL2 p = mix > (REAL)0 ? momentum_steer(carried[i], mix, fx[i], fy[i]) : carried[i];
  REAL dx = gx + beta * p.x;
  REAL dy = gy + beta * p.y;
  if (dx * fx[i] + dy * fy[i] < (REAL)0) {
    dx = gx;
    dy = gy;
  }
  if (r0[i] > (REAL)0) {
    const REAL cap = r0[i] / (REAL)3;
    const REAL len = sqrt(metric_norm2(m11[i], m12[i], m22[i], dx, dy));
    if (len > cap) {
      const REAL s = cap / len;
      dx = dx * s;
      dy = dy * s;
    }
  }
  dx_io[i] = dx;
  dy_io[i] = dy;
  carried[i] = (REAL2)(dx, dy);
}

// StepBackend::reduce in metric mode: per node |F|_M and the kinetic term dt^2 |F|_M^2 / 8 (the
// reference's expressions); the host sums them in node order.
__kernel __attribute__((reqd_work_group_size(WG_SIZE, 1, 1))) void metric_force_norms(
    const int n, __global const uchar* kind, __global const REAL* fx, __global const REAL* fy, __global const REAL* dt2,
    __global const REAL* m11, __global const REAL* m12, __global const REAL* m22, __global REAL* norm_out,
    __global REAL* kinetic_out) {
  const int i = get_global_id(0);
  if (i >= n) return;
  if (kind[i] == 0) {
    norm_out[i] = (REAL)0;
    kinetic_out[i] = (REAL)0;
    return;
  }
#if PDMESH_DOUBLE
  const REAL f2 = metric_norm2(m11[i], m12[i], m22[i], fx[i], fy[i]);
  norm_out[i] = sqrt(f2);
  kinetic_out[i] = REAL_C(0.125) * dt2[i] * f2;  // the reference's
#else
  const float f = metric_force_norm(m11[i], m12[i], m22[i], fx[i], fy[i]);
  norm_out[i] = f;
  kinetic_out[i] = REAL_C(0.125) * dt2[i] * f * f;
#endif
}
