// The background spacing field on the device: the same lookup and bilinear interpolation as
// host/spacing/background_field.cpp (background_locate, background_interpolate), over the flat
// arrays of BackgroundFieldData, plus the domain tag of the leaf; and a test kernel.
// Contraction into fma would make the device differ from the host in the last bits.
#pragma OPENCL FP_CONTRACT OFF

// Leaf of (px, py) and its local coordinates (*u, *v) in [0, 1]. Every step is exact, as on the host.
int bg_locate(REAL px, REAL py, REAL origin_x, REAL origin_y, REAL inv_root_size, int grid,
              __global const int* root_node, __global const int* node_child, REAL* u_out, REAL* v_out) {
  const REAL t = (px - origin_x) * inv_root_size;
  const REAL s = (py - origin_y) * inv_root_size;
  const REAL ft = floor(t);
  const REAL fs = floor(s);
  const REAL last = (REAL)(grid - 1);
  // NaN compares false everywhere, so it lands in cell 0 at u = 0, as on the host.
  const int gx = !(ft >= (REAL)0) ? 0 : (ft > last ? grid - 1 : (int)ft);
  const int gy = !(fs >= (REAL)0) ? 0 : (fs > last ? grid - 1 : (int)fs);
  REAL u = t - (REAL)gx;
  REAL v = s - (REAL)gy;
  u = !(u >= (REAL)0) ? (REAL)0 : (u > (REAL)1 ? (REAL)1 : u);
  v = !(v >= (REAL)0) ? (REAL)0 : (v > (REAL)1 ? (REAL)1 : v);
  int node = root_node[gy * grid + gx];
  int child = node_child[node];
  // A valid tree ends within 20 levels; the bound only guards against corrupt data.
  for (int level = 0; child >= 0 && level < 32; ++level) {
    const int cx = u >= (REAL)0.5 ? 1 : 0;
    const int cy = v >= (REAL)0.5 ? 1 : 0;
    u = (REAL)2 * u - (REAL)cx;
    v = (REAL)2 * v - (REAL)cy;
    node = child + cx + 2 * cy;
    child = node_child[node];
  }
  *u_out = u;
  *v_out = v;
  return -1 - child;
}

REAL spacing_at(REAL px, REAL py, REAL origin_x, REAL origin_y, REAL inv_root_size, int grid,
                __global const int* root_node, __global const int* node_child, __global const int* leaf_corner,
                __global const REAL* corner_q) {
  REAL u, v;
  const int leaf = bg_locate(px, py, origin_x, origin_y, inv_root_size, grid, root_node, node_child, &u, &v);
  const REAL q00 = corner_q[leaf_corner[4 * leaf + 0]];
  const REAL q10 = corner_q[leaf_corner[4 * leaf + 1]];
  const REAL q01 = corner_q[leaf_corner[4 * leaf + 2]];
  const REAL q11 = corner_q[leaf_corner[4 * leaf + 3]];
  return ((REAL)1 - v) * (((REAL)1 - u) * q00 + u * q10) + v * (((REAL)1 - u) * q01 + u * q11);
}

// 0: surely inside the domain, 1: near the boundary (use the exact test), 2: surely outside.
int domain_tag_at(REAL px, REAL py, REAL origin_x, REAL origin_y, REAL inv_root_size, int grid,
                  __global const int* root_node, __global const int* node_child, __global const int* leaf_tag) {
  REAL u, v;
  return leaf_tag[bg_locate(px, py, origin_x, origin_y, inv_root_size, grid, root_node, node_child, &u, &v)];
}

// Test kernel: spacing and tag at n points.
__kernel __attribute__((reqd_work_group_size(WG_SIZE, 1, 1)))
void spacing_lookup(const int n, __global const REAL* px, __global const REAL* py, const REAL origin_x,
                    const REAL origin_y, const REAL inv_root_size, const int grid, __global const int* root_node,
                    __global const int* node_child, __global const int* leaf_corner, __global const int* leaf_tag,
                    __global const REAL* corner_q, __global REAL* out_q, __global int* out_tag) {
  const int i = get_global_id(0);
  if (i >= n) return;
  out_q[i] = spacing_at(px[i], py[i], origin_x, origin_y, inv_root_size, grid, root_node, node_child, leaf_corner,
                        corner_q);
  out_tag[i] = domain_tag_at(px[i], py[i], origin_x, origin_y, inv_root_size, grid, root_node, node_child, leaf_tag);
}
