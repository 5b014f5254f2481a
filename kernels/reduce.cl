// The step sums on the device (mirror of host/sim/reference/time_step.cpp, reduce): per work-group
// partial sums in local memory (a fixed tree order, no float atomics); the host adds the partials in
// group order. WG_SIZE must be a power of two.
#pragma OPENCL FP_CONTRACT OFF

// Tree-reduces v over the work-group into v[0]: sums for slot < sum_slots, maxima after.
// values: REAL[PARTIALS * WG_SIZE] in local memory, laid out slot-major. The CPU shape
// (PDMESH_FORCE_LOOP_VECTOR) walks the same tree, level by level in the same pairs, on work-item 0
// alone: the same bits, two barriers instead of one per level (PoCL runs each region between barriers
// as a loop over all the group's work-items, most of them idle in a tree's upper levels).
// device_step 1.49-1.80 -> 1.46-1.72 ms per iteration on 30P30N's curves with momentum.
void group_reduce(__local REAL* values, const int slots, const int sum_slots) {
#if PDMESH_FORCE_LOOP_VECTOR
  barrier(CLK_LOCAL_MEM_FENCE);
  if (get_local_id(0) == 0) {
    for (int s = 0; s < slots; ++s) {
      __local REAL* v = values + s * WG_SIZE;
      for (int width = WG_SIZE / 2; width > 0; width /= 2) {
        for (int k = 0; k < width; ++k) {
          const REAL a = v[k], b = v[k + width];
          v[k] = s < sum_slots ? a + b : (b > a ? b : a);
        }
      }
    }
  }
  barrier(CLK_LOCAL_MEM_FENCE);
#else
  const int l = get_local_id(0);
  for (int width = WG_SIZE / 2; width > 0; width /= 2) {
    barrier(CLK_LOCAL_MEM_FENCE);
    if (l < width) {
      for (int s = 0; s < slots; ++s) {
        const REAL a = values[s * WG_SIZE + l], b = values[s * WG_SIZE + l + width];
        values[s * WG_SIZE + l] = s < sum_slots ? a + b : (b > a ? b : a);
      }
    }
  }
  barrier(CLK_LOCAL_MEM_FENCE);
#endif
}

// Values one work-group writes and another work-group of the same launch reads (boundary_snap_rule's
// partials, read by its last group; kernels/boundary.cl): OpenCL 1.2 orders nothing between work-groups
// but atomics, so both sides go through 32-bit integer atomics (a double as two halves; the reader
// reads only after every writer counted itself done, so the halves belong together).
void atomic_store_real(__global REAL* p, const REAL v) {
#if PDMESH_DOUBLE
  const int2 h = as_int2(v);
  atomic_xchg((volatile __global int*)p, h.x);
  atomic_xchg((volatile __global int*)p + 1, h.y);
#else
  atomic_xchg((volatile __global int*)p, as_int(v));
#endif
}
REAL atomic_load_real(__global REAL* p) {
#if PDMESH_DOUBLE
  return as_double((int2)(atomic_or((volatile __global int*)p, 0), atomic_or((volatile __global int*)p + 1, 0)));
#else
  return as_float(atomic_or((volatile __global int*)p, 0));
#endif
}

// |F| = sqrt(fx^2 + fy^2). Double: that expression (the reference's). Float: fx^2 overflows past
// |F| ~ 1.8e19 (a node closer than ~q/30 to another), so large forces are scaled by the exact power
// of two 2^-64 before squaring and the root scaled back: no overflow below |F| = FLT_MAX.
REAL force_norm(const REAL fx, const REAL fy) {
#if PDMESH_DOUBLE
  return sqrt(fx * fx + fy * fy);
#else
  if (fmax(fabs(fx), fabs(fy)) > 0x1p60f) {
    const float sx = fx * 0x1p-64f, sy = fy * 0x1p-64f;
    return sqrt(sx * sx + sy * sy) * 0x1p64f;
  }
  return sqrt(fx * fx + fy * fy);
#endif
}

// partials[4 g + k]: k = 0 sum |F|, 1 sum kinetic, 2 moving count, 3 max |F| of group g.
__kernel __attribute__((reqd_work_group_size(WG_SIZE, 1, 1))) void reduce(const int n, __global const uchar* kind,
                                                                          __global const REAL* fx,
                                                                          __global const REAL* fy,
                                                                          __global const REAL* dt2,
                                                                          __global REAL* partials) {
  __local REAL values[4 * WG_SIZE];
  const int i = get_global_id(0), l = get_local_id(0);
  const int moving = i < n && kind[i] != 0;
  const REAL f = moving ? force_norm(fx[i], fy[i]) : (REAL)0;
  values[l] = f;
#if PDMESH_DOUBLE
  values[WG_SIZE + l] = moving ? REAL_C(0.125) * dt2[i] * (fx[i] * fx[i] + fy[i] * fy[i]) : (REAL)0;  // the reference's
#else
  values[WG_SIZE + l] = moving ? REAL_C(0.125) * dt2[i] * f * f : (REAL)0;  // f^2 could overflow in float
#endif
  values[2 * WG_SIZE + l] = moving ? (REAL)1 : (REAL)0;
  values[3 * WG_SIZE + l] = f;
  group_reduce(values, 4, 3);
  if (l < 4) partials[4 * get_group_id(0) + l] = values[l * WG_SIZE];
}
