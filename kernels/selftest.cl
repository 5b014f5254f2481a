// Small kernels for `pdmesh devices --check`, --precision auto and the OpenCL infrastructure tests.
#pragma OPENCL FP_CONTRACT OFF

// y[i] = a * x[i] + i, computed in REAL, guarded for the rounded-up global size.
__kernel __attribute__((reqd_work_group_size(WG_SIZE, 1, 1))) void selftest_axpy(const int n, const REAL a,
                                                                                 __global const REAL* x,
                                                                                 __global REAL* y) {
  const int i = get_global_id(0);
  if (i >= n) return;
  y[i] = a * x[i] + (REAL)i;
}

// The arithmetic rate probe (opencl/precision_probe.cpp): `rounds` multiply-adds in four independent
// dependent chains per work-item (a -> a b + c stays bounded for |b| < 1), one store so nothing is
// optimised away. Timed in float and in double, it measures how much slower the device's fp64 is.
__kernel __attribute__((reqd_work_group_size(WG_SIZE, 1, 1))) void selftest_rate(const int rounds, const REAL b,
                                                                                 const REAL c, __global REAL* out) {
  const int i = get_global_id(0);
  REAL a0 = (REAL)(i & 1023) * REAL_C(0.0009765625), a1 = a0 + (REAL)1, a2 = a0 + (REAL)2, a3 = a0 + (REAL)3;
  for (int r = 0; r < rounds; ++r) {
    a0 = a0 * b + c;
    a1 = a1 * b + c;
    a2 = a2 * b + c;
    a3 = a3 * b + c;
  }
  out[i] = (a0 + a1) + (a2 + a3);
}

// out[k] = row_base(node[k], stride) (common.cl): the 64-bit row offsets every kernel uses, checked
// on the device's own compiler past 2^31 (tests/test_device_row_offsets.cpp).
__kernel __attribute__((reqd_work_group_size(WG_SIZE, 1, 1))) void selftest_row_base(const int n, const int stride,
                                                                                     __global const int* node,
                                                                                     __global long* out) {
  const int k = get_global_id(0);
  if (k >= n) return;
  out[k] = row_base(node[k], stride);
}
