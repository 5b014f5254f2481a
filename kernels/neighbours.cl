// Step 1 on the device (mirror of host/sim/reference/binning.cpp, build_neighbours) over the
// multi-level hashed cell grids the host flattened (host/opencl/neighbour_grids.cpp), in two passes:
//   build_neighbours: every node m scans only the cumulative grid C_L of its own level L (levels <= L).
//     An interior m writes the j within its radius r_m to its own row (index); and m appends itself
//     to the scatter row of every finer interior j (level < L) within r_j (scatter_index, slot from an
//     atomic count), since r_j < r_m puts m inside j's search box but in no grid j scans. This replaces
//     j's lookups in the exact grid of every coarser level (13 levels on 30P30N: a third of the gather's
//     time). The two parts live in separate buffers, so no two work-items ever write the same slot
//     (they once shared the row, owner from the front and scatters from the back, and collided in
//     rows that overflowed: a data race, undefined in the OpenCL memory model).
//   finish_neighbours: joins the two parts and sorts the row by node index; a row whose parts
//     overflow the stride is scanned again the reference way (own cumulative grid, then the exact grid
//     of every coarser level) with a bounded sorted insertion, so it holds the `stride` smallest
//     indices, as the reference's sorted-then-truncated row.
// Row offsets are 64-bit (row_base, common.cl).
#pragma OPENCL FP_CONTRACT OFF

// splitmix64 finaliser over both cell coordinates (the reference's hash_key).
ulong nb_hash(long cx, long cy) {
  ulong h = ((ulong)cx * 0x9E3779B97F4A7C15UL) ^ (ulong)cy;
  h ^= h >> 30;
  h *= 0xBF58476D1CE4E5B9UL;
  h ^= h >> 27;
  h *= 0x94D049BB133111EBUL;
  h ^= h >> 31;
  return h;
}

long nb_cell_coord(REAL v, REAL inv_cell) {
  const REAL c = floor(v * inv_cell);
  return (long)clamp(c, -REAL_C(4.0e18), REAL_C(4.0e18));
}

// Dense cell id of (cx, cy) in grid g, -1 when the cell is empty.
int nb_find(int g, long cx, long cy, __global const int* grid_table_offset, __global const int* grid_table_mask,
            __global const long* table_cx, __global const long* table_cy, __global const int* table_id) {
  const int off = grid_table_offset[g];
  const ulong mask = (ulong)grid_table_mask[g];
  for (ulong s = nb_hash(cx, cy) & mask;; s = (s + 1) & mask) {
    const int id = table_id[off + (int)s];
    if (id < 0) return -1;
    if (table_cx[off + (int)s] == cx && table_cy[off + (int)s] == cy) return id;
  }
}

// The reference-order scan of one row (overflowing rows only): every node within r2 of (xi, yi) in the
// own cumulative grid and every coarser exact grid, inserted in order keeping the `stride` smallest
// indices in index[base ..]; returns the true count.
int nb_scan(const int i, const REAL xi, const REAL yi, const REAL box, const REAL r2, const int own,
            const int levels, const int stride, const long base, uint* examined,
            __global const REAL* x, __global const REAL* y, __global const REAL* grid_inv_cell,
            __global const int* grid_table_offset, __global const int* grid_table_mask,
            __global const int* grid_start_offset, __global const int* grid_nodes_offset,
            __global const long* table_cx, __global const long* table_cy, __global const int* table_id,
            __global const int* cell_start, __global const int* cell_nodes, __global int* index) {
  int count = 0;
  for (int lv = own; lv < levels; ++lv) {
    const int g = lv == own ? 2 * lv : 2 * lv + 1;
    const REAL inv_cell = grid_inv_cell[g];
    if (inv_cell == (REAL)0) continue;
    const long x0 = nb_cell_coord(xi - box, inv_cell), x1 = nb_cell_coord(xi + box, inv_cell);
    const long y0 = nb_cell_coord(yi - box, inv_cell), y1 = nb_cell_coord(yi + box, inv_cell);
    const int start_off = grid_start_offset[g], nodes_off = grid_nodes_offset[g];
    for (long cy = y0; cy <= y1; ++cy) {
      for (long cx = x0; cx <= x1; ++cx) {
        const int id = nb_find(g, cx, cy, grid_table_offset, grid_table_mask, table_cx, table_cy, table_id);
        if (id < 0) continue;
        const int end = cell_start[start_off + id + 1];
        for (int k = cell_start[start_off + id]; k < end; ++k) {
          const int j = cell_nodes[nodes_off + k];
          if (j == i) continue;
          ++*examined;
          const REAL dx = x[j] - xi, dy = y[j] - yi;
          if (dx * dx + dy * dy > r2) continue;
          // Bounded sorted insertion: keep the `stride` smallest indices in ascending order.
          int slot = min(count, stride);
          ++count;
          if (slot == stride && j > index[base + stride - 1]) continue;
          if (slot == stride) --slot;
          while (slot > 0 && index[base + slot - 1] > j) {
            index[base + slot] = index[base + slot - 1];
            --slot;
          }
          index[base + slot] = j;
        }
      }
    }
  }
  return count;
}

// Kernel arguments: per grid g (2 per occupied level: cumulative C_L at 2L, exact E_L at 2L+1; absent
// grids have inv_cell 0): inverse cell size, hash-table offset and mask, offsets into cell_start
// (cells + 1 entries per grid) and cell_nodes. Outputs: own_count and index (the node's own part of its
// row), scatter_count (zeroed by the host) and scatter_index (the part other nodes scattered, in
// slot order); counters[3] += pairs examined.
__kernel __attribute__((reqd_work_group_size(WG_SIZE, 1, 1)))
void build_neighbours(const int n, const int stride, const REAL radius_factor,
                      __global const REAL* x, __global const REAL* y, __global const REAL* q,
                      __global const uchar* kind, __global const int* prev, __global const int* next,
                      __global const int* level, __global const REAL* grid_inv_cell,
                      __global const int* grid_table_offset, __global const int* grid_table_mask,
                      __global const int* grid_start_offset, __global const int* grid_nodes_offset,
                      __global const long* table_cx, __global const long* table_cy, __global const int* table_id,
                      __global const int* cell_start, __global const int* cell_nodes, __global int* own_count,
                      __global volatile int* scatter_count, __global int* scatter_index, __global int* index,
                      __global uint* counters) {
  __local uint local_examined;
  if (get_local_id(0) == 0) local_examined = 0;
  barrier(CLK_LOCAL_MEM_FENCE);
  const int i = get_global_id(0);
  if (i < n) {
    const long base = row_base(i, stride);
    const int kind_i = kind[i];
    int count = 0;
    uint examined = 0;
    if (kind_i == 1) {
      index[base] = prev[i];
      index[base + 1] = next[i];
    }
    {  // every kind scans: boundary and fixed nodes scatter to finer interior rows too
      const REAL xi = x[i], yi = y[i];
      const REAL r = radius_factor * q[i], r2 = r * r;
#if PDMESH_DOUBLE
      const REAL box = r;
#else
      // Cells were assigned on the host in double: widen the box so float rounding cannot drop a cell.
      const REAL box = r * REAL_C(1.0001) + (fabs(xi) + fabs(yi)) * REAL_C(1e-6);
#endif
      const int own = level[i], g = 2 * own;
      const REAL inv_cell = grid_inv_cell[g];
      const long x0 = nb_cell_coord(xi - box, inv_cell), x1 = nb_cell_coord(xi + box, inv_cell);
      const long y0 = nb_cell_coord(yi - box, inv_cell), y1 = nb_cell_coord(yi + box, inv_cell);
      const int start_off = grid_start_offset[g], nodes_off = grid_nodes_offset[g];
      for (long cy = y0; cy <= y1; ++cy) {
        for (long cx = x0; cx <= x1; ++cx) {
          const int id = nb_find(g, cx, cy, grid_table_offset, grid_table_mask, table_cx, table_cy, table_id);
          if (id < 0) continue;
          const int end = cell_start[start_off + id + 1];
          for (int k = cell_start[start_off + id]; k < end; ++k) {
            const int j = cell_nodes[nodes_off + k];
            if (j == i) continue;
            ++examined;
            // -(x[i] - x[j]) exactly: the same squared distance row j's own scan would compute.
            const REAL dx = x[j] - xi, dy = y[j] - yi, d2 = dx * dx + dy * dy;
            if (kind_i == 2 && d2 <= r2) {
              if (count < stride) index[base + count] = j;
              ++count;
            }
            if (level[j] < own && kind[j] == 2) {
              const REAL rj = radius_factor * q[j];
              if (d2 <= rj * rj) {
                const int s = atomic_inc(&scatter_count[j]);
                if (s < stride) scatter_index[row_base(j, stride) + s] = i;
              }
            }
          }
        }
      }
      if (kind_i == 1) count = 2;
    }
    own_count[i] = count;
    atomic_add(&local_examined, examined);
  }
  barrier(CLK_LOCAL_MEM_FENCE);
  if (get_local_id(0) == 0) atomic_add(&counters[3], local_examined);
}

// Pass 2 (see the top): count_out = own + scattered (the true count), rows sorted and -1 padded;
// counters[2] = max count (atomic max), counters[4] = pairs within (sum over interior rows).
__kernel __attribute__((reqd_work_group_size(WG_SIZE, 1, 1)))
void finish_neighbours(const int n, const int stride, const int levels, const REAL radius_factor,
                       __global const REAL* x, __global const REAL* y, __global const REAL* q,
                       __global const uchar* kind, __global const int* level, __global const REAL* grid_inv_cell,
                       __global const int* grid_table_offset, __global const int* grid_table_mask,
                       __global const int* grid_start_offset, __global const int* grid_nodes_offset,
                       __global const long* table_cx, __global const long* table_cy, __global const int* table_id,
                       __global const int* cell_start, __global const int* cell_nodes,
                       __global const int* scatter_count, __global const int* scatter_index,
                       __global int* count_out, __global int* index, __global uint* counters) {
  __local uint local_within;
  __local int local_max;
  if (get_local_id(0) == 0) {
    local_within = 0;
    local_max = 0;
  }
  barrier(CLK_LOCAL_MEM_FENCE);
  const int i = get_global_id(0);
  if (i < n) {
    const long base = row_base(i, stride);
    int count = count_out[i];
    if (kind[i] == 2) {
      const int scattered = scatter_count[i];
      const int own_part = count;
      count += scattered;
      if (count > stride) {
        uint again = 0;
        const REAL xi = x[i], yi = y[i];
        const REAL r = radius_factor * q[i];
#if PDMESH_DOUBLE
        const REAL box = r;
#else
        const REAL box = r * REAL_C(1.0001) + (fabs(xi) + fabs(yi)) * REAL_C(1e-6);
#endif
        nb_scan(i, xi, yi, box, r * r, level[i], levels, stride, base, &again, x, y, grid_inv_cell,
                grid_table_offset, grid_table_mask, grid_start_offset, grid_nodes_offset, table_cx, table_cy,
                table_id, cell_start, cell_nodes, index);
      } else {
        // The scattered part goes behind the own part, then one insertion sort of the row.
        for (int t = 0; t < scattered; ++t) index[base + own_part + t] = scatter_index[base + t];
        for (int a = 1; a < count; ++a) {
          const int v = index[base + a];
          int b = a;
          while (b > 0 && index[base + b - 1] > v) {
            index[base + b] = index[base + b - 1];
            --b;
          }
          index[base + b] = v;
        }
      }
      atomic_add(&local_within, (uint)count);
    }
    for (int k = min(count, stride); k < stride; ++k) index[base + k] = -1;
    count_out[i] = count;
    atomic_max(&local_max, count);
  }
  barrier(CLK_LOCAL_MEM_FENCE);
  if (get_local_id(0) == 0) {
    atomic_max((__global int*)&counters[2], local_max);
    atomic_add(&counters[4], local_within);
  }
}
