// Step 1 on the device (mirror of host/sim/reference/binning.cpp, build_neighbours) over the
// multi-level grids kernels/binning.cl built on the device, into compact rows (CSR): row i holds
// count[i] entries at entries[offset[i] ..], in a slot of capacity offset[i + 1] - offset[i]. Offsets
// are 64-bit (ulong): the entries pass 2^31 long before the node count does. A build:
//   row_capacity_scan, row_block_offsets, row_offsets_add: the capacity of each row (the count the
//     last build found plus slack, host/opencl/device_neighbours.cpp) and its offset, an exclusive
//     prefix sum over work-groups (per group in local memory, the group totals by one work-group).
//   gather_rows: every node m scans only the cumulative grid C_L of its own level L (levels <= L). An
//     interior m appends the j within its radius r_m to its own row; and m appends itself to the row
//     of every finer interior j (level < L) within r_j, since r_j < r_m puts m inside j's search box
//     but in no grid j scans (this replaces j's lookups in the grid of every coarser level: 13
//     levels on 30P30N, a third of the gather's time). Every slot comes from an integer atomic on the
//     row's count, so no two work-items ever write one slot; an entry past the capacity is counted
//     but not written (the row overflows).
//   A build without the last counts (a run's first, or after the node set changed) first runs
//   gather_rows with `counting` set on a sample of the nodes (every sample_stride-th scans; stride 1:
//   all, exact counts): rows are only counted (no entry, no spill list). row_level_tally sums the
//   sampled counts of the interior rows per grid level; the host turns them into one estimated
//   capacity per level (device_neighbours.cpp), row_capacity_scan lays the rows out with it, and
//   the gather writes them; the few rows that outgrow it move behind the others (relocate_rows).
//   With pair_skin = s c > 0 (the device run's lists: radius_factor = c (1 + s), c the cut-off, s the
//     skin) a finer interior row i also takes a coarser m (level[m] > level[i]) within c q_i + s c q_m,
//     more than r_i: the pair's skin is the coarser node's, so that either node may use half of its own
//     skin (host/opencl/device_run.hpp). pair_skin = 0 gives the reference's rows.
//   Every building pass also finds, per node m, the largest ratio rho_m = q_m / q_j over the interior j
//     of its own level within its radius r_m (below 2: a level spans a factor 2 of radii), as m's skin
//     class (skin_class[m]), and their maximum (counters[ROW_RATIO]): how much of its skin m may use.
//   sort_rows: sorts each interior row by node index (the reference's order: forces are summed in
//     it) and counts the rows that outgrew their capacities; the host then builds again with
//     capacities from the counts just found, which are exact.

// The row counters' slots (ROW_OUTGROWN ... ROW_SPARE_FULL) come from the program builder
// (host/opencl/step_program.hpp, RowCounter).
#ifndef ROW_SPARE_FULL
#error "the row counter slots (ROW_*) must be defined by the program builder"
#endif
#pragma OPENCL FP_CONTRACT OFF

// Row capacities c + (c >> spare_shift) + spare_min from the counts c of the last build, scanned per
// work-group: offset[i + 1] = the group's inclusive sum up to i, block_total[g] = the group's total.
// row_block_offsets and row_offsets_add finish the prefix sum. With `estimate` set (a build without
// counts), an interior row takes its level's estimated capacity level_cap[level[i]] instead, a
// boundary row that of its 2 entries, any other that of none.
__kernel __attribute__((reqd_work_group_size(WG_SIZE, 1, 1))) void row_capacity_scan(
    const int n, const int spare_shift, const int spare_min, __global const int* count, const int estimate,
    __global const uchar* kind, __global const int* level, __global const int* level_cap, __global ulong* offset,
    __global ulong* block_total) {
  __local ulong tmp[WG_SIZE];
  const int i = get_global_id(0);
  const int c = i >= n ? 0 : !estimate ? max(count[i], 0) : kind[i] == 1 ? 2 : 0;
  ulong cap = i < n ? (ulong)c + (ulong)(c >> spare_shift) + (ulong)spare_min : 0;
  if (i < n && estimate && kind[i] == 2)
    cap = (ulong)max(level_cap[clamp(level[i], 0, PDMESH_GRID_LEVELS - 1)], spare_min);
  const ulong s = group_inclusive_scan(cap, tmp);
  if (i < n) offset[i + 1] = s;
  if (get_local_id(0) == WG_SIZE - 1) block_total[get_group_id(0)] = s;
}

// One work-group: block_total[g] becomes the exclusive prefix sum of the group totals (the offset of
// group g's first row), block_total[groups] the sum of all capacities.
__kernel __attribute__((reqd_work_group_size(WG_SIZE, 1, 1))) void row_block_offsets(const int groups,
                                                                                     __global ulong* block_total) {
  __local ulong tmp[WG_SIZE];
  const int l = get_local_id(0);
  ulong carry = 0;
  for (int b0 = 0; b0 < groups; b0 += WG_SIZE) {
    const ulong v = b0 + l < groups ? block_total[b0 + l] : 0;
    const ulong s = group_inclusive_scan(v, tmp);
    if (b0 + l < groups) block_total[b0 + l] = carry + s - v;
    carry += tmp[WG_SIZE - 1];
    barrier(CLK_LOCAL_MEM_FENCE);  // everyone has read tmp before the next scan writes it
  }
  if (l == 0) block_total[groups] = carry;
}

// Also sets each row's count to 0 for the gather (row_capacity_scan has read it), but only when the
// binning left usable grids: a pass whose grids were too small gathers nothing and runs again with the
// grids at their size, and from these counts (carried over an event, or the last build's), not from
// zero counts, which would make every row outgrow and the pass after it gather a third time.
__kernel __attribute__((reqd_work_group_size(WG_SIZE, 1, 1))) void row_offsets_add(const int n, __global ulong* offset,
                                                                                   __global const ulong* block_total,
                                                                                   __global const int* bin_state,
                                                                                   __global int* count) {
  const int i = get_global_id(0);
  if (i == 0) offset[0] = 0;
  if (i < n) {
    offset[i + 1] += block_total[get_group_id(0)];
    if (bin_ok(bin_state, n)) count[i] = 0;
  }
}

// Writes j into slot s of row r (a slot reserved from the row's count): inside the capacity in place;
// past it, (r, j) goes to the spill list (counters[ROW_SPILLED] counts them, `spill_capacity` are kept)
// for relocate_rows.
void row_place(const int r, const ulong s, const int j, __global const ulong* offset, const ulong entries_size,
               __global int* entries, const uint spill_capacity, __global int* spill, __global uint* counters) {
  const ulong slot = offset[r] + s;
  if (slot < offset[r + 1] && slot < entries_size) {
    entries[slot] = j;
  } else {
    const uint p = atomic_inc(&counters[ROW_SPILLED]);
    if (p < spill_capacity) {
      spill[2 * p] = r;
      spill[2 * p + 1] = j;
    }
  }
}

// Appends j to row r (see the top): the slot from the row's count (row_place). A counting pass
// (`counting`) only counts.
void row_append(const int r, const int j, __global const ulong* offset, __global volatile int* count,
                const ulong entries_size, __global int* entries, const uint spill_capacity, __global int* spill,
                __global uint* counters, const int counting) {
  if (counting) {
    atomic_inc(&count[r]);
    return;
  }
  row_place(r, (ulong)atomic_inc(&count[r]), j, offset, entries_size, entries, spill_capacity, spill, counters);
}

#if PDMESH_FORCE_LOOP_VECTOR
// row_append for k entries of one row at once: one integer atomic reserves k slots (on a CPU device
// the atomic per entry was a quarter of gather_rows' time: a locked instruction each). The entries a
// row ends up with are the same whatever the batching (sort_rows orders them; an entry past the
// capacity spills, as row_append's); only the order before the sort differs.
void row_append_batch(const int r, const int* js, const int k, __global const ulong* offset,
                      __global volatile int* count, const ulong entries_size, __global int* entries,
                      const uint spill_capacity, __global int* spill, __global uint* counters, const int counting) {
  const ulong s = (ulong)atomic_add(&count[r], k);
  if (counting) return;
  // The bounds once for the batch: in place when all k fit (row_place's test for each), else entry by entry.
  const ulong first = offset[r] + s;
  if (first + (ulong)k <= min(offset[r + 1], entries_size)) {
    for (int t = 0; t < k; ++t) entries[first + (ulong)t] = js[t];
    return;
  }
  for (int t = 0; t < k; ++t)
    row_place(r, s + (ulong)t, js[t], offset, entries_size, entries, spill_capacity, spill, counters);
}

// The CPU loop walks a range of buckets (gather_node) 8 entries at a time in vector types (PoCL's CPU
// device does not vectorise across work-items; forces.cl's GATHER8_XY and compress builtins, which the
// program places before this file): the tag, distance and cell tests of 8 entries at once, without a branch on
// each entry's outcome (a bucket's entries are in node order, its cells mixed: the scalar loop's
// branches on them mispredicted at most entries). The accepted pairs (j and d2) are compressed into a
// private list of GATHER_LIST_CAP; gather_emit appends them to the rows when it is nearly full and
// after the scan. The rows end up with the same entries (sort_rows orders them; an entry past the
// capacity spills, as row_append's); only the order of the appends differs.
#define GATHER_LIST_CAP 64
#if PDMESH_DOUBLE
#define GATHER_MASK_T long
#else
#define GATHER_MASK_T int
#endif

// Appends the k listed pairs (i, js[t]) at squared distances d2s[t] of node i (kind kind_i, level own,
// spacing qi) to the rows, as the GPU-shaped loop does per pair: all to i's own row when i is
// interior (one batch), each to the row of a finer interior j within j's radius; returns q_min lowered
// by the listed interior j of i's own level (building passes only).
REAL gather_emit(const int i, const int kind_i, const int own, const REAL qi, const int* js, const REAL* d2s,
                 const int k, REAL q_min, const REAL radius_factor, const REAL pair_skin, __global const REAL* q,
                 __global const uchar* kind, __global const int* level, __global const ulong* offset,
                 __global volatile int* count, const ulong entries_size, __global int* entries,
                 const uint spill_capacity, __global int* spill, __global uint* counters, const int counting) {
  if (kind_i == 2)
    row_append_batch(i, js, k, offset, count, entries_size, entries, spill_capacity, spill, counters, counting);
  for (int t = 0; t < k; ++t) {
    const int j = js[t];
    if (kind[j] != 2) continue;
    const int level_j = level[j];
    if (!counting && level_j == own) q_min = fmin(q_min, q[j]);
    if (level_j < own) {
      // The finer row's radius, widened for its coarser neighbour to c q_j + s c q_i (pair_skin =
      // s c; see the top): r_i = c (1 + s) q_i bounds it, so this scan sees every such pair.
      const REAL qj = q[j];
      const REAL rj = radius_factor * qj + (qj < qi ? pair_skin * (qi - qj) : (REAL)0);
      if (d2s[t] <= rj * rj)
        row_append(j, i, offset, count, entries_size, entries, spill_capacity, spill, counters, counting);
    }
  }
  return q_min;
}
#endif

// Node i's scan (see the top): its rows' entries appended, its skin class written; *examined_out: the
// candidates it examined, *ratio_out: its spacing ratio scaled for counters[ROW_RATIO] (0: none).
void gather_node(const int i, const REAL radius_factor, __global const REAL2* xy, __global const REAL* q,
                 __global const uchar* kind, __global const int* prev, __global const int* next,
                 __global const int* level, __global const int* grid_mask, __global const uint* grid_bucket_offset,
                 __global const REAL* grid_inv_cell, __global const uint* bucket, __global const int* grid_nodes,
                 __global const ulong* offset, __global volatile int* count, const ulong entries_size,
                 __global int* entries, const uint spill_capacity, __global int* spill, __global uint* counters,
                 const int counting, __global uchar* skin_class, const REAL pair_skin, uint* examined_out,
                 uint* ratio_out) {
  *ratio_out = 0;
  const int kind_i = kind[i];
  uint examined = 0;
  // The smallest q_j of the interior j within r_i (building passes only): q_i over it is the largest
  // spacing ratio of a pair this scan owns, for the device run's skin-use limit (see the top).
  REAL q_min = INFINITY;
  if (kind_i == 1) {  // [prev, next], in that order (no other work-item writes a boundary row)
    row_append(i, prev[i], offset, count, entries_size, entries, spill_capacity, spill, counters, counting);
    row_append(i, next[i], offset, count, entries_size, entries, spill_capacity, spill, counters, counting);
  }
  {  // every kind scans: boundary and fixed nodes scatter to finer interior rows too
#if PDMESH_FORCE_LOOP_VECTOR
    int list_j[GATHER_LIST_CAP];
    REAL list_d2[GATHER_LIST_CAP];
    int listed = 0;
#endif
    const REAL2 pi = xy[i];  // positions: x, y interleaved (the step's layout)
    const REAL xi = pi.x, yi = pi.y;
    const REAL qi = q[i];
    const REAL r = radius_factor * qi, r2 = r * r;
#if PDMESH_DOUBLE
    const REAL box = r;
#else
    // The cells and the box are computed in float: widen the box so rounding cannot drop a cell.
    const REAL box = r * REAL_C(1.0001) + (fabs(xi) + fabs(yi)) * REAL_C(1e-6);
#endif
    const int own = level[i];
    const REAL inv_cell = grid_inv_cell[own];
    const long x0 = nb_cell_coord(xi - box, inv_cell), x1 = nb_cell_coord(xi + box, inv_cell);
    const long y0 = nb_cell_coord(yi - box, inv_cell), y1 = nb_cell_coord(yi + box, inv_cell);
    const uint bucket_base = grid_bucket_offset[own];
    const ulong mask = (ulong)grid_mask[own];
    // Cells of the box that no point within r reaches (its corners) are skipped: the gap from
    // (xi, yi) to the cell, shrunk by `slack` (far above the rounding of the cell bounds and of d2),
    // exceeds r. Only the work changes: a node in a skipped cell is farther than r, in no row.
    const REAL cell = (REAL)1 / inv_cell;
#if PDMESH_DOUBLE
    const REAL slack = (fabs(xi) + fabs(yi) + r + cell) * REAL_C(1e-12);
#else
    const REAL slack = (fabs(xi) + fabs(yi) + r + cell) * REAL_C(1e-4);
#endif
    // A box spanning at most 5 cells a side (r < 2 cells: always in double) lies in at most 2 x 2
    // blocks of 4 x 4 cells (nb_bucket), whose hashes the CPU loop computes once (the GPU-shaped
    // program hashes per cell: 4 more 64-bit values cost 22 VGPRs on gfx90a). In a grid of 16 buckets or
    // more, two cells share a bucket only at the same place in their blocks, so two cells of such a
    // box in one bucket are (4a, 4b) apart with a, b in {-1, 0, 1}, and their tags differ (nb_tag
    // is linear: its top 4 bits move by those of 4a M + 4b N, which are neither 0 nor 15 for these
    // eight offsets; tests/test_device_neighbours.cpp checks the constants). So an entry carrying a
    // probed cell's tag from another cell lies outside the box: a candidate inside the box by more
    // than `slack` on both axes is of the probed cell without the cell test (the same rows); nearer
    // the box's edge, in larger boxes (float) or in smaller grids the cell test decides, as before.
    const int small_box = x1 - x0 <= 4 && y1 - y0 <= 4;
#if PDMESH_FORCE_LOOP_VECTOR
    const ulong bx0 = (ulong)x0 >> 2, by0 = (ulong)y0 >> 2;
    const ulong h00 = nb_hash((long)bx0, (long)by0), h10 = nb_hash((long)((ulong)x1 >> 2), (long)by0);
    const ulong h01 = nb_hash((long)bx0, (long)((ulong)y1 >> 2));
    const ulong h11 = nb_hash((long)((ulong)x1 >> 2), (long)((ulong)y1 >> 2));
#endif
#if PDMESH_FORCE_LOOP_VECTOR
    const int tags_apart = small_box && mask >= 15;
#else
    const int tags_apart = 0;  // GPU-shaped: floor() is cheap there, and this path cost 6 VGPRs (gfx90a)
#endif
    const REAL inside = r - slack;
#if PDMESH_FORCE_LOOP_VECTOR
    // The probed cells of one row of the box inside one 4 x 4 block (at most 4, consecutive in cx) are
    // consecutive buckets when the block's hash is shared (small_box) and the grid has 16 buckets or
    // more, so their entries are one range of grid_nodes: it is scanned as one, 8 entries at a time, each
    // entry tested against the tag of the cell whose bucket holds it (lane index against the buckets'
    // bounds). The same entries meet the same tests as in a scan per cell (the same candidates, pairs
    // and `examined`), in fewer and fuller chunks with one bucket lookup per range. Other boxes take
    // one cell per range (the condition is tags_apart's).
    for (long cy = y0; cy <= y1; ++cy) {
      const REAL gy = fmax(fmax((REAL)cy * cell - yi, yi - (REAL)(cy + 1) * cell) - slack, (REAL)0);
      const int second_y = ((ulong)cy >> 2) != by0;
      const REAL gy2 = gy * gy;
      for (long cx = x0; cx <= x1; ++cx) {
        const REAL gx = fmax(fmax((REAL)cx * cell - xi, xi - (REAL)(cx + 1) * cell) - slack, (REAL)0);
        if (gx * gx + gy2 > r2) continue;
        // The range: cx .. last, the cells of this row and block that the gap test keeps (an interval:
        // the gap grows away from xi).
        long last = cx;
        while (tags_apart && last < x1 && (((ulong)last + 1UL) & 3UL) != 0) {
          const long nx = last + 1;
          const REAL nxg = fmax(fmax((REAL)nx * cell - xi, xi - (REAL)(nx + 1) * cell) - slack, (REAL)0);
          if (nxg * nxg + gy2 > r2) break;
          last = nx;
        }
        const int cells = (int)(last - cx) + 1;
        uint b;
        if (small_box) {
          const int second_x = ((ulong)cx >> 2) != bx0;
          const ulong hb = second_y ? (second_x ? h11 : h01) : (second_x ? h10 : h00);
          const uint in_block = (uint)((((ulong)cy & 3UL) << 2) | ((ulong)cx & 3UL));
          b = bucket_base + (uint)(((hb << 4) | in_block) & mask);
        } else {
          b = bucket_base + nb_bucket(cx, cy, mask);
        }
        const uint begin = b > 0 ? bucket[b - 1] : 0, end = bucket[b + (uint)cells - 1];
        // Entry k lies in the bucket of cell cx + (k >= s1) + (k >= s2) + (k >= s3); the bounds past
        // the range's cells never match.
        const uint s1 = cells > 1 ? bucket[b] : UINT_MAX, s2 = cells > 2 ? bucket[b + 1] : UINT_MAX;
        const uint s3 = cells > 3 ? bucket[b + 2] : UINT_MAX;
        const int tag0 = (int)nb_tag(cx, cy);
        const int tag1 = cells > 1 ? (int)nb_tag(cx + 1, cy) : 0, tag2 = cells > 2 ? (int)nb_tag(cx + 2, cy) : 0;
        const int tag3 = cells > 3 ? (int)nb_tag(cx + 3, cy) : 0;
        for (uint k0 = begin; k0 < end; k0 += 8) {
          int8 e;
          if (k0 + 8 <= end) {
            e = vload8(0, grid_nodes + k0);
          } else {  // the range's last, partial chunk: the lanes past it hold i (never a candidate)
#if defined(PACK_MASK_BITS)
            // A masked load (no fault past the end, no store-to-load stall of lane-by-lane writes).
            e = __builtin_astype(__builtin_ia32_loaddqusi256_mask((const int*)(ulong)(grid_nodes + k0),
                                                                  __builtin_astype((int8)(i), pack_v8si),
                                                                  (uchar)((1U << (end - k0)) - 1U)),
                                 int8);
#else
            e = (int8)(i);
            for (uint c = 0; k0 + c < end; ++c) ((int*)&e)[c] = grid_nodes[k0 + c];
#endif
          }
          const uint8 lane = (uint8)(k0) + (uint8)(0, 1, 2, 3, 4, 5, 6, 7);
          const int8 in1 = lane >= (uint8)(s1), in2 = lane >= (uint8)(s2), in3 = lane >= (uint8)(s3);
          const int8 want =
              select(select(select((int8)(tag0), (int8)(tag1), in1), (int8)(tag2), in2), (int8)(tag3), in3);
          const int8 j = e & (int8)((int)GRID_NODE_MASK);
          const int8 candidate = ((e & (int8)((int)~GRID_NODE_MASK)) == want) & (j != (int8)(i));
          REAL8 px, py;
#if defined(PACK_MASK_BITS) && PDMESH_DOUBLE
          // A chunk without a candidate loads no position. The others load every lane's x and y by one
          // 16-byte load each (j is a node whatever its cell: every load is valid; `bits` holds candidates
          // only): on AVX-512 CPUs such as Zen 5 they cost less than two masked vgatherdpd of the
          // candidates' lanes, in cache and out of it.
          const uchar cand_bits = (uchar)__builtin_ia32_cvtd2mask256(__builtin_astype(candidate, pack_v8si));
          if (!cand_bits) continue;
          examined += popcount((uint)cand_bits);
          {
            const REAL2 p0 = xy[j.s0], p1 = xy[j.s1], p2 = xy[j.s2], p3 = xy[j.s3], p4 = xy[j.s4], p5 = xy[j.s5],
                        p6 = xy[j.s6], p7 = xy[j.s7];
            px = (REAL8)(p0.x, p1.x, p2.x, p3.x, p4.x, p5.x, p6.x, p7.x);
            py = (REAL8)(p0.y, p1.y, p2.y, p3.y, p4.y, p5.y, p6.y, p7.y);
          }
#else
#if defined(PACK_MASK_BITS)
          examined += popcount((uint)(uchar)__builtin_ia32_cvtd2mask256(__builtin_astype(candidate, pack_v8si)));
#else
          examined += (uint)COUNT8(candidate);
#endif
          GATHER8_XY(xy, j, px, py);  // j is a node whatever its cell: every lane's load is valid
#endif
          // -(x[i] - x[j]) exactly, as the GPU-shaped loop below.
          const REAL8 dx = px - (REAL8)(xi), dy = py - (REAL8)(yi), d2 = dx * dx + dy * dy;
#if defined(PACK_MASK_BITS)
          // The tests as mask bits (no vector of masks or lane array in private memory): the cell test
          // near the box's edge (see `tags_apart`) reads the lane's node and position again, rarely.
          uint bits = (uint)(uchar)__builtin_ia32_cvtd2mask256(__builtin_astype(candidate, pack_v8si)) &
                      (uint)(uchar)PACK_MASK_BITS(d2 <= (REAL8)(r2));
          const uint check_bits =
              tags_apart
                  ? bits & ~(uint)(uchar)PACK_MASK_BITS((fabs(dx) < (REAL8)(inside)) & (fabs(dy) < (REAL8)(inside)))
                  : bits;
          if (check_bits) {
            for (int c = 0; c < 8; ++c) {
              if (!((check_bits >> c) & 1U)) continue;
              const uint k = k0 + (uint)c;
              const long lane_cx = cx + (long)(k >= s1) + (long)(k >= s2) + (long)(k >= s3);
              const REAL2 pc = xy[grid_nodes[k] & (int)GRID_NODE_MASK];
              if (nb_cell_coord(pc.x, inv_cell) != lane_cx || nb_cell_coord(pc.y, inv_cell) != cy) bits &= ~(1U << c);
            }
          }
          vstore8(
              __builtin_astype(__builtin_ia32_compresssi256_mask(__builtin_astype(j, pack_v8si),
                                                                 __builtin_astype((int8)(0), pack_v8si), (uchar)bits),
                               int8),
              0, list_j + listed);
          vstore8(__builtin_astype(PACK_COMPRESS_REAL(__builtin_astype(d2, pack_v8real),
                                                      __builtin_astype((REAL8)((REAL)0), pack_v8real), (uchar)bits),
                                   REAL8),
                  0, list_d2 + listed);
          listed += (int)popcount(bits);
#else
          MASK8 use = CONVERT_MASK8(candidate) & (d2 <= (REAL8)(r2));
          const MASK8 fast = tags_apart ? (fabs(dx) < (REAL8)(inside)) & (fabs(dy) < (REAL8)(inside)) : (MASK8)(0);
          const MASK8 check = use & ~fast;
          if (any(check)) {  // the cell test near the box's edge (see `tags_apart`), against the lane's cell
            for (int c = 0; c < 8; ++c) {
              const uint k = k0 + (uint)c;
              const long lane_cx = cx + (long)(k >= s1) + (long)(k >= s2) + (long)(k >= s3);
              if (((GATHER_MASK_T*)&check)[c] && (nb_cell_coord(((REAL*)&px)[c], inv_cell) != lane_cx ||
                                                  nb_cell_coord(((REAL*)&py)[c], inv_cell) != cy))
                ((GATHER_MASK_T*)&use)[c] = 0;
            }
          }
          for (int c = 0; c < 8; ++c) {
            list_j[listed] = ((int*)&j)[c];
            list_d2[listed] = ((REAL*)&d2)[c];
            listed -= (int)((GATHER_MASK_T*)&use)[c];
          }
#endif
          if (listed > GATHER_LIST_CAP - 8) {  // room for the next chunk's 8
            q_min = gather_emit(i, kind_i, own, qi, list_j, list_d2, listed, q_min, radius_factor, pair_skin, q, kind,
                                level, offset, count, entries_size, entries, spill_capacity, spill, counters, counting);
            listed = 0;
          }
        }
        cx = last;
      }
    }
#else
    for (long cy = y0; cy <= y1; ++cy) {
      const REAL gy = fmax(fmax((REAL)cy * cell - yi, yi - (REAL)(cy + 1) * cell) - slack, (REAL)0);
      for (long cx = x0; cx <= x1; ++cx) {
        const REAL gx = fmax(fmax((REAL)cx * cell - xi, xi - (REAL)(cx + 1) * cell) - slack, (REAL)0);
        if (gx * gx + gy * gy > r2) continue;
        const uint b = bucket_base + nb_bucket(cx, cy, mask);
        const uint tag = nb_tag(cx, cy);
        const uint end = bucket[b];
        for (uint k = b > 0 ? bucket[b - 1] : 0; k < end; ++k) {
          const uint e = (uint)grid_nodes[k];
          if ((e & ~GRID_NODE_MASK) != tag) continue;  // another cell (most of them: no position loads)
          const int j = (int)(e & GRID_NODE_MASK);
          if (j == i) continue;
          ++examined;
          // -(x[i] - x[j]) exactly: the same squared distance row j's own scan would compute.
          const REAL2 pj = xy[j];
          const REAL dx = pj.x - xi, dy = pj.y - yi, d2 = dx * dx + dy * dy;
          // Every pair this scan lists is within r: r_j < r_i for a finer j (level[j] < own), so
          // d2 <= r_j^2 implies d2 <= r2. Farther candidates need no cell test.
          if (!(d2 <= r2)) continue;
          // Only the probed cell's nodes (a bucket may hold other cells, one of them probed too);
          // see `tags_apart` above.
          if (!(tags_apart && fabs(dx) < inside && fabs(dy) < inside) &&
              (nb_cell_coord(pj.x, inv_cell) != cx || nb_cell_coord(pj.y, inv_cell) != cy))
            continue;
          if (kind_i == 2)
            row_append(i, j, offset, count, entries_size, entries, spill_capacity, spill, counters, counting);
          const int interior_j = kind[j] == 2;
          if (interior_j && !counting && level[j] == own) q_min = fmin(q_min, q[j]);
          if (level[j] < own && interior_j) {
            // The finer row's radius, widened for its coarser neighbour to c q_j + s c q_i (pair_skin =
            // s c; see the top): r_i = c (1 + s) q_i bounds it, so this scan sees every such pair.
            const REAL qj = q[j];
            const REAL rj = radius_factor * qj + (qj < qi ? pair_skin * (qi - qj) : (REAL)0);
            if (d2 <= rj * rj)
              row_append(j, i, offset, count, entries_size, entries, spill_capacity, spill, counters, counting);
          }
        }
      }
    }
#endif
#if PDMESH_FORCE_LOOP_VECTOR
    if (listed > 0)
      q_min = gather_emit(i, kind_i, own, qi, list_j, list_d2, listed, q_min, radius_factor, pair_skin, q, kind, level,
                          offset, count, entries_size, entries, spill_capacity, spill, counters, counting);
#endif
  }
  *examined_out = examined;
  const REAL ratio = q_min < INFINITY ? q[i] / q_min : (REAL)0;
  if (q_min < INFINITY) {
    // Rounded up to the next 1/ROW_RATIO_SCALE (the unit covers a float quotient's rounding).
    const REAL scaled = ratio * (REAL)ROW_RATIO_SCALE;
    *ratio_out = scaled < (REAL)2.0e9 ? (uint)scaled + 1U : 2000000000U;
  }
  // Node i's skin class: ceil(SKIN_CLASS_STEPS log2 rho) for rho = max(1, ratio), plus a margin far
  // above log2's rounding; 255 at most (larger ratios: the host scales its limit, device_run.hpp).
  if (!counting) {
    const REAL steps = ratio > (REAL)1 ? (REAL)SKIN_CLASS_STEPS * log2(ratio) + REAL_C(0.001) : (REAL)0;
    skin_class[i] = steps < (REAL)254 ? (uchar)ceil(steps) : (uchar)255;
  }
}

// Kernel arguments: per grid g (2 per occupied level: cumulative C_L at 2L, exact E_L at 2L+1; absent
// grids have inv_cell 0): inverse cell size, hash-table offset and mask, offsets into cell_start
// (cells + 1 entries per grid) and cell_nodes. Rows: offset (n + 1, from the scan), count (zeroed by
// the host), entries (entries_size slots), the spill list. counters[ROW_EXAMINED] += pairs examined.
__kernel __attribute__((reqd_work_group_size(WG_SIZE, 1, 1))) void gather_rows(
    const int n, const REAL radius_factor, __global const REAL2* xy, __global const REAL* q, __global const uchar* kind,
    __global const int* prev, __global const int* next, __global const int* level, __global const int* bin_state,
    __global const int* grid_mask, __global const uint* grid_bucket_offset, __global const REAL* grid_inv_cell,
    __global const uint* bucket, __global const int* grid_nodes, __global const ulong* offset,
    __global volatile int* count, const ulong entries_size, __global int* entries, const uint spill_capacity,
    __global int* spill, __global uint* counters, const int counting, const int sample_stride,
    __global uchar* skin_class, const REAL pair_skin) {
#if PDMESH_FORCE_LOOP_VECTOR
  // The CPU shape scans the group's nodes in work-item 0 alone, without barriers: PoCL gives each
  // work-item of a kernel with barriers its own copy of the private arrays (the scan's lists, ~1 KB:
  // a 67 KB stack frame for the group, more than the L1 cache), one copy here.
  if (get_local_id(0) != 0 || !bin_ok(bin_state, n)) return;
  uint group_examined = 0, group_ratio = 0;
  const int first = (int)(get_global_id(0) - get_local_id(0));  // launched over ceil(n / sample_stride) work-items
  for (int l = 0; l < WG_SIZE; ++l) {
    const int i = (first + l) * sample_stride;
    if (i >= n) break;
    uint examined, ratio;
    gather_node(i, radius_factor, xy, q, kind, prev, next, level, grid_mask, grid_bucket_offset, grid_inv_cell, bucket,
                grid_nodes, offset, count, entries_size, entries, spill_capacity, spill, counters, counting, skin_class,
                pair_skin, &examined, &ratio);
    group_examined += examined;
    group_ratio = max(group_ratio, ratio);
  }
  atomic_add(&counters[ROW_EXAMINED], group_examined);
  atomic_max(&counters[ROW_RATIO], group_ratio);
#else
  __local uint local_examined, local_ratio;
  if (get_local_id(0) == 0) {
    local_examined = 0;
    local_ratio = 0;
  }
  barrier(CLK_LOCAL_MEM_FENCE);
  const int i = (int)get_global_id(0) * sample_stride;  // launched over ceil(n / sample_stride) work-items
  if (i < n && bin_ok(bin_state, n)) {
    uint examined, ratio;
    gather_node(i, radius_factor, xy, q, kind, prev, next, level, grid_mask, grid_bucket_offset, grid_inv_cell, bucket,
                grid_nodes, offset, count, entries_size, entries, spill_capacity, spill, counters, counting, skin_class,
                pair_skin, &examined, &ratio);
    atomic_add(&local_examined, examined);
    atomic_max(&local_ratio, ratio);
  }
  barrier(CLK_LOCAL_MEM_FENCE);
  if (get_local_id(0) == 0) {
    atomic_add(&counters[ROW_EXAMINED], local_examined);
    atomic_max(&counters[ROW_RATIO], local_ratio);
  }
#endif
}

// After a sampled counting pass (see the top): per level L, tally[2 L] += the counts of its interior
// rows and tally[2 L + 1] += its interior nodes; tally[2 PDMESH_GRID_LEVELS] += the boundary nodes.
// Sums per work-group in local memory first (the levels are few, their atomics contended).
__kernel __attribute__((reqd_work_group_size(WG_SIZE, 1, 1))) void row_level_tally(const int n,
                                                                                   __global const uchar* kind,
                                                                                   __global const int* level,
                                                                                   __global const int* count,
                                                                                   __global uint* tally) {
  __local uint sums[2 * PDMESH_GRID_LEVELS + 1];
  const int l = get_local_id(0);
  for (int k = l; k < 2 * PDMESH_GRID_LEVELS + 1; k += WG_SIZE) sums[k] = 0;
  barrier(CLK_LOCAL_MEM_FENCE);
  const int i = get_global_id(0);
  if (i < n) {
    if (kind[i] == 2) {
      const int L = clamp(level[i], 0, PDMESH_GRID_LEVELS - 1);  // in range whenever the binning succeeded
      atomic_add(&sums[2 * L], (uint)max(count[i], 0));
      atomic_inc(&sums[2 * L + 1]);
    } else if (kind[i] == 1) {
      atomic_inc(&sums[2 * PDMESH_GRID_LEVELS]);
    }
  }
  barrier(CLK_LOCAL_MEM_FENCE);
  for (int k = l; k < 2 * PDMESH_GRID_LEVELS + 1; k += WG_SIZE)
    if (sums[k]) atomic_add(&tally[k], sums[k]);
}

// 2^(k / SKIN_CLASS_STEPS), k < SKIN_CLASS_STEPS (the program builder's, skin_class_factor's table).
__constant REAL skin_class_roots[SKIN_CLASS_STEPS] = {SKIN_CLASS_ROOTS};

// The share of node i's skin its position p and spacing qn have used since the lists were built
// (position pb, spacing qb): its distance from pb plus the cut-off's growth with q, over the skin,
// divided by the share node i may use, 2^(-1 - c / SKIN_CLASS_STEPS) for its skin class c (written by
// gather_rows; host/opencl/device_run.hpp): the lists hold while every node's result stays at most 1
// (less the host's margin). The factor 2^(1 + c / SKIN_CLASS_STEPS) from a table and exact powers of 2,
// as the host computes it (an exp2 per node and iteration cost a libm call on PoCL). One expression
// for device_step, refresh_budgets and boundary_snap, so that they agree bit for bit.
// skin_use_parts: the expression's operands (the squared distance, the growth, the divisor, the factor),
// for callers that take the square root and division of several nodes at once (device_step's CPU shape).
void skin_use_parts(const REAL2 p, const REAL qn, const REAL2 pb, const REAL qb, const REAL cutoff,
                    const REAL skin_cutoff, const uchar skin_class, REAL* d2, REAL* grow, REAL* divisor, REAL* factor) {
  const REAL ex = p.x - pb.x, ey = p.y - pb.y;
  *d2 = ex * ex + ey * ey;
  *grow = qn > qb ? cutoff * (qn - qb) : (REAL)0;
  *divisor = skin_cutoff * qb;
  *factor = (REAL)(2 << (skin_class / SKIN_CLASS_STEPS)) * skin_class_roots[skin_class % SKIN_CLASS_STEPS];
}
REAL skin_use_of(const REAL2 p, const REAL qn, const REAL2 pb, const REAL qb, const REAL cutoff, const REAL skin_cutoff,
                 const uchar skin_class) {
  REAL d2, grow, divisor, factor;
  skin_use_parts(p, qn, pb, qb, cutoff, skin_cutoff, skin_class, &d2, &grow, &divisor, &factor);
  return (sqrt(d2) + grow) / divisor * factor;
}

// Insertion sort of entries[base .. base + c) ascending.
void insertion_sort_row(__global int* entries, const ulong base, const int c) {
  for (int a = 1; a < c; ++a) {
    const int v = entries[base + a];
    int b = a;
    while (b > 0 && entries[base + b - 1] > v) {
      entries[base + b] = entries[base + b - 1];
      --b;
    }
    entries[base + b] = v;
  }
}

// sort_row: entries[base .. base + c) ascending. On x86 with AVX-512 (PoCL's CPU device on such a
// machine) a row of up to RANK_SORT_CAP entries is sorted by rank: entry a goes to the place given by
// how many entries of the row are smaller (a row's entries are distinct nodes), counted 16 at a time
// by a compare into a mask and a popcount. The insertion sort's branches mispredicted at nearly every
// entry (rows come in cell order, not index order); the rank sort takes ~1 % of pdmesh bench's samples
// on 30P30N's curves (docs/journal/). Longer rows and other
// devices keep the insertion sort; both give the one ascending order.
#if defined(__x86_64__) && defined(__AVX512F__)
#define RANK_SORT_CAP 256
typedef int rank_v16si __attribute__((vector_size(64)));
// A row of up to 32 entries (most rows) is ranked in two registers: its entries loaded by masked
// loads (the lanes past the row hold INT_MAX, no load past it), each entry broadcast and compared
// with all 32 lanes at once, each lane's rank counted in its own lane (no popcount chain, no copy of
// the row into private memory to be read back as vectors). The same ranks, so the same order. Each
// register's entries go to their ranks by one masked scatter (the row's lanes only; ranks are distinct)
// from the registers, not through private arrays read back lane by lane.
#define RANK_SORT_REG 32
#define RANK_SCATTER(out, bits, rank, v)                                             \
  __builtin_ia32_scattersiv16si((out), (bits), __builtin_astype((rank), rank_v16si), \
                                __builtin_astype((v), rank_v16si), 4)
void sort_row_reg(__global int* entries, const ulong base, const int c) {
  const uint m = c >= 32 ? 0xFFFFFFFFU : (1U << c) - 1U;
  const rank_v16si pad = __builtin_astype((int16)(INT_MAX), rank_v16si);
  const int16 v0 =
      __builtin_astype(__builtin_ia32_loaddqusi512_mask((const int*)(ulong)(entries + base), pad, (ushort)m), int16);
  const int16 v1 = __builtin_astype(
      __builtin_ia32_loaddqusi512_mask((const int*)(ulong)(entries + base + 16), pad, (ushort)(m >> 16)), int16);
  int16 r0 = (int16)(0), r1 = (int16)(0);
  for (int b = 0; b < c; ++b) {
    const int16 x = (int16)(entries[base + b]);
    r0 -= x < v0;  // -1 where true
    r1 -= x < v1;
  }
  int* out = (int*)(ulong)(entries + base);
  RANK_SCATTER(out, (ushort)m, r0, v0);
  RANK_SCATTER(out, (ushort)(m >> 16), r1, v1);
}

// Rows of 33 to 64 entries the same way in four registers (the device run's lists with the Verlet skin
// average ~31 entries a row on 30P30N, many rows are longer): the chunked rank count below takes a
// compare, a mask move and a popcount per 16 entries for each entry.
#define RANK_SORT_REG4 64
void sort_row_reg4(__global int* entries, const ulong base, const int c) {
  const ulong m = c >= 64 ? ~0UL : (1UL << c) - 1UL;
  const rank_v16si pad = __builtin_astype((int16)(INT_MAX), rank_v16si);
  const int* row = (const int*)(ulong)(entries + base);
  const int16 v0 = __builtin_astype(__builtin_ia32_loaddqusi512_mask(row, pad, (ushort)m), int16);
  const int16 v1 = __builtin_astype(__builtin_ia32_loaddqusi512_mask(row + 16, pad, (ushort)(m >> 16)), int16);
  const int16 v2 = __builtin_astype(__builtin_ia32_loaddqusi512_mask(row + 32, pad, (ushort)(m >> 32)), int16);
  const int16 v3 = __builtin_astype(__builtin_ia32_loaddqusi512_mask(row + 48, pad, (ushort)(m >> 48)), int16);
  int16 r0 = (int16)(0), r1 = (int16)(0), r2 = (int16)(0), r3 = (int16)(0);
  for (int b = 0; b < c; ++b) {
    const int16 x = (int16)(entries[base + b]);
    r0 -= x < v0;  // -1 where true
    r1 -= x < v1;
    r2 -= x < v2;
    r3 -= x < v3;
  }
  int* out = (int*)(ulong)(entries + base);
  RANK_SCATTER(out, (ushort)m, r0, v0);
  RANK_SCATTER(out, (ushort)(m >> 16), r1, v1);
  RANK_SCATTER(out, (ushort)(m >> 32), r2, v2);
  RANK_SCATTER(out, (ushort)(m >> 48), r3, v3);
}

void sort_row(__global int* entries, const ulong base, const int c) {
  if (c <= RANK_SORT_REG) {
    sort_row_reg(entries, base, c);
    return;
  }
  if (c <= RANK_SORT_REG4) {
    sort_row_reg4(entries, base, c);
    return;
  }
  if (c > RANK_SORT_CAP) {
    insertion_sort_row(entries, base, c);
    return;
  }
  int v[RANK_SORT_CAP], out[RANK_SORT_CAP];
  const int chunks = (c + 15) >> 4;
  for (int k = 0; k < c; ++k) v[k] = entries[base + k];
  for (int k = c; k < chunks << 4; ++k) v[k] = INT_MAX;  // never below an entry (node indices < INT_MAX)
  for (int a = 0; a < c; ++a) {
    const rank_v16si x = __builtin_astype((int16)(v[a]), rank_v16si);
    uint rank = 0;
    for (int h = 0; h < chunks; ++h)
      rank += popcount(
          (uint)__builtin_ia32_cmpd512_mask(__builtin_astype(vload16(h, v), rank_v16si), x, 1, (ushort)0xFFFF));
    out[rank] = v[a];
  }
  for (int k = 0; k < c; ++k) entries[base + k] = out[k];
}
#else
void sort_row(__global int* entries, const ulong base, const int c) { insertion_sort_row(entries, base, c); }
#endif

// Pass 2 (see the top): interior rows sorted ascending (insertion sort: rows are short and nearly
// sorted by cell order). counters[ROW_OUTGROWN] = the rows that outgrew their capacities,
// counters[ROW_ENTRIES] = the entries of all rows, counters[ROW_LARGEST] = the largest row (atomic
// max), counters[ROW_WITHIN] = pairs within (interior rows).
// No row is sorted in a pass the host will run again: its grids were too small (nothing gathered), or
// more entries spilled than the spill list holds (every run's first build, laid out from a sample).
#if PDMESH_FORCE_LOOP_VECTOR
// The CPU shape takes the group's rows in work-item 0, without barriers or local atomics (PoCL runs a
// group's work-items as one loop per region between barriers): the same sums and maximum.
__kernel __attribute__((reqd_work_group_size(WG_SIZE, 1, 1))) void sort_rows(
    const int n, __global const uchar* kind, __global const ulong* offset, __global const int* count,
    const ulong entries_size, __global int* entries, __global uint* counters, __global const int* bin_state,
    const uint spill_capacity) {
  const int i0 = (int)get_group_id(0) * WG_SIZE, end = min(i0 + WG_SIZE, n);
  if (get_local_id(0) != 0 || i0 >= n) return;
  const int sorting = bin_ok(bin_state, n) && counters[ROW_SPILLED] <= spill_capacity;
  uint within = 0, total = 0, overflow = 0;
  int largest = 0;
  for (int i = i0; i < end; ++i) {
    const int c = count[i];
    const ulong base = offset[i];
    if (base + (ulong)c > offset[i + 1] || offset[i + 1] > entries_size)
      ++overflow;
    else if (kind[i] == 2 && sorting)
      sort_row(entries, base, c);
    if (kind[i] == 2) within += (uint)c;
    total += (uint)c;
    largest = max(largest, c);
  }
  if (overflow) atomic_add(&counters[ROW_OUTGROWN], overflow);
  atomic_add(&counters[ROW_ENTRIES], total);
  atomic_max((__global int*)&counters[ROW_LARGEST], largest);
  atomic_add(&counters[ROW_WITHIN], within);
}
#else
__kernel __attribute__((reqd_work_group_size(WG_SIZE, 1, 1))) void sort_rows(
    const int n, __global const uchar* kind, __global const ulong* offset, __global const int* count,
    const ulong entries_size, __global int* entries, __global uint* counters, __global const int* bin_state,
    const uint spill_capacity) {
  __local uint local_within, local_total, local_overflow;
  __local int local_max;
  if (get_local_id(0) == 0) {
    local_within = 0;
    local_total = 0;
    local_overflow = 0;
    local_max = 0;
  }
  barrier(CLK_LOCAL_MEM_FENCE);
  const int i = get_global_id(0);
  if (i < n) {
    const int c = count[i];
    const ulong base = offset[i];
    if (base + (ulong)c > offset[i + 1] || offset[i + 1] > entries_size) {
      atomic_inc(&local_overflow);
    } else if (kind[i] == 2 && bin_ok(bin_state, n) && counters[ROW_SPILLED] <= spill_capacity) {
      sort_row(entries, base, c);
    }
    if (kind[i] == 2) atomic_add(&local_within, (uint)c);
    atomic_add(&local_total, (uint)c);
    atomic_max(&local_max, c);
  }
  barrier(CLK_LOCAL_MEM_FENCE);
  if (get_local_id(0) == 0) {
    if (local_overflow) atomic_add(&counters[ROW_OUTGROWN], local_overflow);
    atomic_add(&counters[ROW_ENTRIES], local_total);
    atomic_max((__global int*)&counters[ROW_LARGEST], local_max);
    atomic_add(&counters[ROW_WITHIN], local_within);
  }
}
#endif

// A row that outgrew its capacity (its entries past it in the spill list) moves to the spare region
// behind the last row, [offset[n], entries_size): relocate_rows copies its kept entries there and
// leaves in its old slot (capacity >= spare_min = 2 entries, every layout) where the row went,
// relative to offset[n], and how many entries it holds there; place_spilled then appends each
// spilled entry to its row through that cursor (integer atomics), and apply_row_moves sorts each moved
// row and points offset[i] at it. Each kernel's work is linear in the rows moved or the entries
// spilled (a layout from a sampled estimate moves ~1% of the rows). The spilled entries' order is the
// atomics': only interior rows can outgrow (a boundary row holds its 2 entries in a capacity of at
// least 2), and they are sorted. counters[ROW_SPARE_USED]: spare entries used; counters[ROW_MOVED]:
// rows moved; counters[ROW_SPARE_FULL]: the spare region was full. When the spill list, the spare
// region or the move list is too small, nothing is moved and the host builds again (the counts are
// exact then).
int rows_move(__global const uint* counters, const uint spill_capacity, const uint move_capacity) {
  return counters[ROW_SPILLED] <= spill_capacity && counters[ROW_OUTGROWN] <= move_capacity;
}

__kernel __attribute__((reqd_work_group_size(WG_SIZE, 1, 1))) void relocate_rows(
    const int n, __global const uchar* kind, __global const ulong* offset, __global const int* count,
    const ulong entries_size, __global int* entries, const uint spill_capacity, __global const int* spill,
    const uint move_capacity, __global int* move_node, __global ulong* move_start, __global uint* counters) {
  const int i = get_global_id(0);
  if (i >= n) return;
  const int c = count[i];
  const ulong base = offset[i], cap = offset[i + 1] - base;
  if (base + (ulong)c <= offset[i + 1] && offset[i + 1] <= entries_size) return;
  if (!rows_move(counters, spill_capacity, move_capacity)) return;
  const ulong rel = (ulong)atomic_add(&counters[ROW_SPARE_USED], (uint)c);
  const ulong start = offset[n] + rel;
  if (start + (ulong)c > entries_size || rel + (ulong)c > (ulong)INT_MAX || cap < 2 || base + 2 > entries_size ||
      kind[i] != 2) {
    atomic_or(&counters[ROW_SPARE_FULL], 1U);  // no room (or no cursor): the host builds again
    return;
  }
  const ulong kept = min(cap, (ulong)c);
  for (ulong k = 0; k < kept; ++k) entries[start + k] = entries[base + k];
  entries[base] = (int)rel;  // the cursor for place_spilled
  entries[base + 1] = (int)kept;
  const uint m = atomic_inc(&counters[ROW_MOVED]);
  move_node[m] = i;
  move_start[m] = start;
}

// One work-item per spilled entry (row r, node j): appended to r's moved row through the cursor
// relocate_rows left in r's old slot.
__kernel __attribute__((reqd_work_group_size(WG_SIZE, 1, 1))) void place_spilled(
    const int n, __global const ulong* offset, __global volatile int* entries, const uint spill_capacity,
    __global const int* spill, const uint move_capacity, __global const uint* counters) {
  const uint p = get_global_id(0);
  if (p >= min(counters[ROW_SPILLED], spill_capacity) || !rows_move(counters, spill_capacity, move_capacity) ||
      counters[ROW_SPARE_FULL])
    return;
  const int r = spill[2 * p];
  const ulong base = offset[r];
  const ulong rel = (ulong)(uint)entries[base];
  const uint k = (uint)atomic_inc(&entries[base + 1]);
  entries[offset[n] + rel + k] = spill[2 * p + 1];
}

__kernel __attribute__((reqd_work_group_size(WG_SIZE, 1, 1))) void apply_row_moves(
    __global const int* move_node, __global const ulong* move_start, __global const uint* counters,
    __global const int* count, __global int* entries, __global ulong* offset) {
  const uint k = get_global_id(0);
  if (k >= counters[ROW_MOVED] || counters[ROW_SPARE_FULL]) return;
  const int i = move_node[k];
  sort_row(entries, move_start[k], count[i]);  // interior rows only move (relocate_rows)
  offset[i] = move_start[k];
}
