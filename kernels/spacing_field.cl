// The background spacing field on the device: the same lookup and bilinear interpolation as
// host/spacing/background_field.cpp (background_locate, background_interpolate), over the flat
// arrays of BackgroundFieldData, plus the domain tag of the leaf; and a test kernel.
// Contraction into fma would make the device differ from the host in the last bits.
#pragma OPENCL FP_CONTRACT OFF

// Top-grid cell of (px, py) (index gy * grid + gx) and the local coordinates (*u, *v) in [0, 1] in it.
int bg_root_cell(REAL px, REAL py, REAL origin_x, REAL origin_y, REAL inv_root_size, int grid, REAL* u_out,
                 REAL* v_out) {
  const REAL t = (px - origin_x) * inv_root_size;
  const REAL s = (py - origin_y) * inv_root_size;
  const REAL ft = floor(t);
  const REAL fs = floor(s);
  const REAL last = (REAL)(grid - 1);
  // NaN compares false everywhere, so it lands in cell 0 at u = 0, as on the host.
  const int gx = !(ft >= (REAL)0) ? 0 : (ft > last ? grid - 1 : (int)ft);
  const int gy = !(fs >= (REAL)0) ? 0 : (fs > last ? grid - 1 : (int)fs);
  const REAL u = t - (REAL)gx;
  const REAL v = s - (REAL)gy;
  *u_out = !(u >= (REAL)0) ? (REAL)0 : (u > (REAL)1 ? (REAL)1 : u);
  *v_out = !(v >= (REAL)0) ? (REAL)0 : (v > (REAL)1 ? (REAL)1 : v);
  return gy * grid + gx;
}

// Descends from tree node `node` to the leaf holding local coordinates (*u, *v), which become the
// leaf's. Every step is exact, as on the host.
int bg_descend(int node, __global const int* node_child, REAL* u_io, REAL* v_io) {
  REAL u = *u_io, v = *v_io;
  int child = node_child[node];
  // A valid tree ends within 20 levels; the bound only guards against corrupt data.
  for (int level = 0; child >= 0 && level < 32; ++level) {
    const int cx = u >= REAL_C(0.5) ? 1 : 0;
    const int cy = v >= REAL_C(0.5) ? 1 : 0;
    u = (REAL)2 * u - (REAL)cx;
    v = (REAL)2 * v - (REAL)cy;
    node = child + cx + 2 * cy;
    child = node_child[node];
  }
  *u_io = u;
  *v_io = v;
  return -1 - child;
}

// Leaf of (px, py) and its local coordinates (*u, *v) in [0, 1].
int bg_locate(REAL px, REAL py, REAL origin_x, REAL origin_y, REAL inv_root_size, int grid,
              __global const int* root_node, __global const int* node_child, REAL* u_out, REAL* v_out) {
  const int root = bg_root_cell(px, py, origin_x, origin_y, inv_root_size, grid, u_out, v_out);
  return bg_descend(root_node[root], node_child, u_out, v_out);
}

// bg_locate with a guess: *leaf_io is a leaf index whose cell (leaf_cell: top-grid cell, level L,
// integer cell coordinates ix, iy below the root) is tested first; only on a miss does it descend.
// Why the shortcut returns bit-identical (u, v): for t = (px - origin) / root_size in [gx, gx + 1)
// bg_root_cell's floor gives gx and u0 = t - gx exactly (Sterbenz, or gx = 0), no clamping. The
// descent's u_k = 2 u_{k-1} - c_k is exact at every level (doubling is exact; 2 u - 1 for 2 u in
// [1, 2) is exact by Sterbenz), so u_L = 2^L u0 - ix exactly, with ix = floor(2^L u0) (the bits
// c_1..c_L); 2^L u0 is exact (a power-of-two scaling) and the difference is representable (it is
// u_L), so one rounded subtraction gives it exactly. The test ix <= 2^L u0 < ix + 1 is that floor.
// Points on the grid's far edges or off it (clamped there), and NaN, fail the test and descend.
// The top-grid cell (gx, gy) of the leaf's index gy * grid + gx is tested as the cell of floor(t),
// floor(s) (gx <= t < gx + 1 holds exactly when floor(t) = gx, gx an integer; on the grid, t >= 0,
// floor is the conversion to int): a multiplication instead of an integer division, the same test.
// Inlined: see bg_spacing_cached (kernels/device_step.cl).
__attribute__((always_inline)) int bg_locate_cached(REAL px, REAL py, int* leaf_io, REAL origin_x, REAL origin_y,
                                                    REAL inv_root_size, int grid, __global const int* root_node,
                                                    __global const int* node_child, __global const int* leaf_cell,
                                                    REAL* u_out, REAL* v_out) {
  const int guess = *leaf_io;
  const int4 cell = vload4(guess, leaf_cell);
  const REAL t = (px - origin_x) * inv_root_size;
  const REAL s = (py - origin_y) * inv_root_size;
  // Only a point on the grid converts to int (NaN and points off it compare false and never match).
  const int on_grid = t >= (REAL)0 && t < (REAL)grid && s >= (REAL)0 && s < (REAL)grid;
  const int cx = on_grid ? (int)t : 0, cy = on_grid ? (int)s : 0;
  const int top = on_grid ? cy * grid + cx : -1;
  const REAL gx = (REAL)cx, gy = (REAL)cy;
  const REAL cells = (REAL)(1 << cell.y);
  const REAL wu = (t - gx) * cells, wv = (s - gy) * cells;
  const REAL ix = (REAL)cell.z, iy = (REAL)cell.w;
  if (top == cell.x && wu >= ix && wu < ix + (REAL)1 && wv >= iy && wv < iy + (REAL)1) {
    *u_out = wu - ix;
    *v_out = wv - iy;
    return guess;
  }
  const int root = bg_root_cell(px, py, origin_x, origin_y, inv_root_size, grid, u_out, v_out);
  const int leaf = bg_descend(root_node[root], node_child, u_out, v_out);
  *leaf_io = leaf;
  return leaf;
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
__kernel __attribute__((reqd_work_group_size(WG_SIZE, 1, 1))) void spacing_lookup(
    const int n, __global const REAL* px, __global const REAL* py, const REAL origin_x, const REAL origin_y,
    const REAL inv_root_size, const int grid, __global const int* root_node, __global const int* node_child,
    __global const int* leaf_corner, __global const int* leaf_tag, __global const REAL* corner_q, __global REAL* out_q,
    __global int* out_tag) {
  const int i = get_global_id(0);
  if (i >= n) return;
  out_q[i] =
      spacing_at(px[i], py[i], origin_x, origin_y, inv_root_size, grid, root_node, node_child, leaf_corner, corner_q);
  out_tag[i] = domain_tag_at(px[i], py[i], origin_x, origin_y, inv_root_size, grid, root_node, node_child, leaf_tag);
}

// Test kernel: bg_locate_cached from guess[i] against bg_locate, at n points: leaf and (u, v) of both.
__kernel __attribute__((reqd_work_group_size(WG_SIZE, 1, 1))) void locate_cached_lookup(
    const int n, __global const REAL* px, __global const REAL* py, const REAL origin_x, const REAL origin_y,
    const REAL inv_root_size, const int grid, __global const int* root_node, __global const int* node_child,
    __global const int* leaf_cell, __global const int* guess, __global int* out_leaf, __global REAL* out_uv) {
  const int i = get_global_id(0);
  if (i >= n) return;
  REAL u, v, cu, cv;
  const int leaf = bg_locate(px[i], py[i], origin_x, origin_y, inv_root_size, grid, root_node, node_child, &u, &v);
  int cached = guess[i];
  bg_locate_cached(px[i], py[i], &cached, origin_x, origin_y, inv_root_size, grid, root_node, node_child, leaf_cell,
                   &cu, &cv);
  out_leaf[2 * i] = leaf;
  out_leaf[2 * i + 1] = cached;
  out_uv[4 * i] = u;
  out_uv[4 * i + 1] = v;
  out_uv[4 * i + 2] = cu;
  out_uv[4 * i + 3] = cv;
}
