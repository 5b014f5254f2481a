// A tiny kernel used by `pdmesh devices --check` and the OpenCL infrastructure tests:
// y[i] = a * x[i] + i, computed in REAL, guarded for the rounded-up global size.
__kernel __attribute__((reqd_work_group_size(WG_SIZE, 1, 1)))
void selftest_axpy(const int n, const REAL a, __global const REAL* x, __global REAL* y) {
  const int i = get_global_id(0);
  if (i >= n) return;
  y[i] = a * x[i] + (REAL)i;
}
