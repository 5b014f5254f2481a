// Binning on the device for the neighbour gather (kernels/neighbours.cl): the reference's multi-level
// grids (host/sim/reference/binning.cpp; host/opencl/neighbour_grids.cpp is the host's flat copy and
// the test oracle) built by a counting sort, so a rebuild uploads no grid and downloads nothing to bin.
// Level of node j: floor(log2(R_j / R_min)), R = radius_factor q; the grid of level L holds the nodes of
// level <= L (the cumulative grid C_L, the only one the gather scans) in cells of R_min 2^L. A grid is
// a hash table of 2^k buckets (k from its member count: about 2 members per bucket), each bucket the
// nodes of the cells hashing to it; the gather keeps the nodes of the probed cell only. Kernels, in
// order (host/opencl/device_neighbours.cpp):
//   bin_bounds: validity (first invalid node, atomic_min) and per-group minima of R;
//   bin_rmin: R_min (one work-group);
//   bin_levels: each node's level, the member count of each level, the top level;
//   bin_plan: one work-item lays out the grids (bucket counts and offsets, inverse cell sizes) and
//     checks them against the buffers' capacities (too small: the host builds again at the sizes
//     it reports);
//   bin_count: per node and grid, atomic_inc on its bucket's count;
//   bucket_scan, row_block_offsets, bucket_offsets_add: exclusive prefix sum of the counts in place;
//   bin_fill: per node and grid, a slot from atomic_inc on its bucket's start, which leaves every
//     bucket's entry holding its end (= the next bucket's start): bucket b is [bucket[b - 1], bucket[b]).
//     The slot holds the node and its cell's tag (GRID_NODE_BITS below).
// Order within a bucket is the atomics' order; the rows the gather makes from it are sorted.
#pragma OPENCL FP_CONTRACT OFF

#ifndef PDMESH_GRID_LEVELS
#error "PDMESH_GRID_LEVELS (grid levels at most, kBinLevels) must be defined by the program builder"
#endif
// bin_state (ints): what the host reads after a build with the row counters. Its slots
// (BIN_FIRST_INVALID, BIN_TOP, BIN_TOO_MANY_LEVELS, BIN_BUCKETS, BIN_MEMBERS, BIN_TOO_SMALL, then
// PDMESH_GRID_LEVELS member counts from BIN_LEVEL_COUNT) are defined by the program builder from
// host/opencl/step_program.hpp's BinStateSlot.
#ifndef BIN_LEVEL_COUNT
#error "the bin_state slots (BIN_*) must be defined by the program builder"
#endif
#define BIN_STATE_SIZE (BIN_LEVEL_COUNT + PDMESH_GRID_LEVELS)
// A grid entry: node | cell tag (host/opencl/step_program.hpp, kGridNodeBits). The tag is the top bits of
// a second hash of the cell, a multiply-add with other constants: the top bits of nb_hash itself agree
// for most cells sharing a bucket (measured: 63% of pairs at 2^16 buckets), this tag for ~1/16.
#ifndef GRID_NODE_BITS
#error "GRID_NODE_BITS (kGridNodeBits) must be defined by the program builder"
#endif
#define GRID_NODE_MASK ((1U << GRID_NODE_BITS) - 1U)
uint nb_tag(const long cx, const long cy) {
  const ulong t = (ulong)cx * 0xD6E8FEB86659FD93UL + (ulong)cy * 0xA0761D6478BD642FUL;
  return (uint)(t >> (32 + GRID_NODE_BITS)) << GRID_NODE_BITS;
}

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

// The bucket of cell (cx, cy) in a grid of mask + 1 buckets: the cell's 4x4 block of cells is hashed,
// and its 16 cells take 16 consecutive buckets (when the grid has 16 or more), so the cells a node's
// search box covers lie in a few runs of buckets and of grid entries instead of one random place
// each (at 1M nodes the gather's probes were cache misses). Blocks are floor(c / 4) in two's
// complement (the unsigned shift keeps negative coordinates consistent; no other property is needed).
uint nb_bucket(const long cx, const long cy, const ulong mask) {
  const ulong h = nb_hash((long)((ulong)cx >> 2), (long)((ulong)cy >> 2));
  return (uint)(((h << 4) | (((ulong)cy & 3UL) << 2) | ((ulong)cx & 3UL)) & mask);
}

// floor(v inv_cell) clamped to +-4e18, as the host's (neighbour_grids.cpp, the reference), by truncation
// and a correction: the same integer for every finite v (the bounds are integers, so clamping first
// commutes with floor; a clamped value converts exactly). PoCL's CPU device expands floor() into a
// branchy sequence that takes a third of the gather's time at 1M nodes (perf); the gather
// calls this for every candidate within the radius.
// The GPU-shaped program (PDMESH_FORCE_LOOP_SCALAR) keeps floor(), one instruction there.
long nb_cell_coord(REAL v, REAL inv_cell) {
#if PDMESH_FORCE_LOOP_VECTOR
  const REAL c = clamp(v * inv_cell, -REAL_C(4.0e18), REAL_C(4.0e18));
  const long t = (long)c;
  return (REAL)t > c ? t - 1 : t;
#else
  return (long)clamp(floor(v * inv_cell), -REAL_C(4.0e18), REAL_C(4.0e18));
#endif
}

// Whether the binning left usable grids (every kernel after bin_levels checks it).
int bin_ok(__global const int* state, const int n) {
  return state[BIN_FIRST_INVALID] >= n && !state[BIN_TOO_MANY_LEVELS] && !state[BIN_TOO_SMALL];
}

// The bucket of node j's cell in grid L: its global index into `bucket`; *tag: the cell's tag.
uint bin_bucket(const REAL xj, const REAL yj, const int L, __global const int* grid_mask,
                __global const uint* grid_bucket_offset, __global const REAL* grid_inv_cell, uint* tag) {
  const REAL inv_cell = grid_inv_cell[L];
  const long cx = nb_cell_coord(xj, inv_cell), cy = nb_cell_coord(yj, inv_cell);
  *tag = nb_tag(cx, cy);
  return grid_bucket_offset[L] + nb_bucket(cx, cy, (ulong)grid_mask[L]);
}

// A node the binning can place: a finite position and a finite q > 0 (any other is reported).
int bin_node_valid(const REAL x, const REAL y, const REAL q) {
  return isfinite(x) && isfinite(y) && isfinite(q) && q > (REAL)0;
}

// The grid level of a node of list radius R_j = `radius`: floor(log2(R_j / R_min)) as the reference
// (R_j / R_min = m 2^e with m in [0.5, 1)), clamped to the last level, where *too_many is set.
int bin_level_of(const REAL radius, const REAL r_min, int* too_many) {
  int e = 0;
  frexp(radius / r_min, &e);
  const int lv = max(0, e - 1);
  if (lv < PDMESH_GRID_LEVELS) return lv;
  *too_many = 1;
  return PDMESH_GRID_LEVELS - 1;
}

// Adds one work-group's member counts per level and its top level (-1: none) to the build's state,
// one global atomic per level the group has.
void bin_add_levels(const int* count, const int top, __global int* state) {
  for (int k = 0; k < PDMESH_GRID_LEVELS; ++k)
    if (count[k] > 0) atomic_add(&state[BIN_LEVEL_COUNT + k], count[k]);
  if (top >= 0) atomic_max(&state[BIN_TOP], top);
}

// state[BIN_FIRST_INVALID] must start at INT_MAX, the other entries at 0 (the host uploads them).
#if PDMESH_FORCE_LOOP_VECTOR
// The CPU shape: work-item 0 takes the group's nodes in a loop, without barriers (a tree reduction's
// barriers cost PoCL a loop over the group's work-items per region). The same minimum and the same
// first invalid node.
__kernel __attribute__((reqd_work_group_size(WG_SIZE, 1, 1))) void bin_bounds(const int n, const REAL radius_factor,
                                                                              __global const REAL2* xy,
                                                                              __global const REAL* q,
                                                                              __global REAL* partial,
                                                                              __global int* state) {
  if (get_local_id(0) != 0) return;
  const int i0 = (int)get_group_id(0) * WG_SIZE, end = min(i0 + WG_SIZE, n);
  REAL r = INFINITY;
  int invalid = INT_MAX;
  for (int i = i0; i < end; ++i) {
    const REAL xi = xy[i].x, yi = xy[i].y, qi = q[i];  // positions: x, y interleaved
    if (!bin_node_valid(xi, yi, qi))
      invalid = min(invalid, i);
    else
      r = fmin(r, radius_factor * qi);
  }
  if (invalid < INT_MAX) atomic_min(&state[BIN_FIRST_INVALID], invalid);
  partial[get_group_id(0)] = r;
}
#else
__kernel __attribute__((reqd_work_group_size(WG_SIZE, 1, 1))) void bin_bounds(const int n, const REAL radius_factor,
                                                                              __global const REAL2* xy,
                                                                              __global const REAL* q,
                                                                              __global REAL* partial,
                                                                              __global int* state) {
  __local REAL m[WG_SIZE];
  const int i = get_global_id(0), l = get_local_id(0);
  REAL r = INFINITY;
  if (i < n) {
    const REAL xi = xy[i].x, yi = xy[i].y, qi = q[i];  // positions: x, y interleaved
    if (!bin_node_valid(xi, yi, qi))
      atomic_min(&state[BIN_FIRST_INVALID], i);
    else
      r = radius_factor * qi;
  }
  m[l] = r;
  barrier(CLK_LOCAL_MEM_FENCE);
  for (int s = WG_SIZE / 2; s > 0; s >>= 1) {
    if (l < s && m[l + s] < m[l]) m[l] = m[l + s];
    barrier(CLK_LOCAL_MEM_FENCE);
  }
  if (l == 0) partial[get_group_id(0)] = m[0];
}
#endif

// One work-group: partial[groups] = the minimum of partial[0 .. groups) (R_min).
__kernel __attribute__((reqd_work_group_size(WG_SIZE, 1, 1))) void bin_rmin(const int groups, __global REAL* partial) {
  __local REAL m[WG_SIZE];
  const int l = get_local_id(0);
  REAL r = INFINITY;
  for (int g = l; g < groups; g += WG_SIZE) r = partial[g] < r ? partial[g] : r;
  m[l] = r;
  barrier(CLK_LOCAL_MEM_FENCE);
  for (int s = WG_SIZE / 2; s > 0; s >>= 1) {
    if (l < s && m[l + s] < m[l]) m[l] = m[l + s];
    barrier(CLK_LOCAL_MEM_FENCE);
  }
  if (l == 0) partial[groups] = m[0];
}

// Each node's level (bin_level_of). The member counts and the top level are tallied per work-group in
// local memory first, then added with one global atomic per level the group has (bin_add_levels): a
// global atomic per node on the same few words had the CPU device's two threads pass their cache line
// back and forth for every node.
// The CPU shape computes and tallies the group's levels in work-item 0, without the barrier.
#if PDMESH_FORCE_LOOP_VECTOR
__kernel __attribute__((reqd_work_group_size(WG_SIZE, 1, 1))) void bin_levels(
    const int n, const int groups, const REAL radius_factor, __global const REAL* q, __global const REAL* partial,
    __global int* level, __global int* state) {
  if (get_local_id(0) != 0 || state[BIN_FIRST_INVALID] < n) return;
  const int i0 = (int)get_group_id(0) * WG_SIZE, end = min(i0 + WG_SIZE, n);
  const REAL r_min = partial[groups];
  int count[PDMESH_GRID_LEVELS];
  for (int k = 0; k < PDMESH_GRID_LEVELS; ++k) count[k] = 0;
  int top = -1, too_many = 0;
  for (int i = i0; i < end; ++i) {
    const int lv = bin_level_of(radius_factor * q[i], r_min, &too_many);
    level[i] = lv;
    ++count[lv];
    top = max(top, lv);
  }
  if (too_many) atomic_or(&state[BIN_TOO_MANY_LEVELS], 1);
  bin_add_levels(count, top, state);
}
#else
__kernel __attribute__((reqd_work_group_size(WG_SIZE, 1, 1))) void bin_levels(
    const int n, const int groups, const REAL radius_factor, __global const REAL* q, __global const REAL* partial,
    __global int* level, __global int* state) {
  __local int levels[WG_SIZE];
  const int i = get_global_id(0), l = get_local_id(0);
  const int valid = state[BIN_FIRST_INVALID] >= n;  // uniform: the same word for every work-item
  int lv = -1;
  if (i < n && valid) {
    int too_many = 0;
    lv = bin_level_of(radius_factor * q[i], partial[groups], &too_many);
    if (too_many) atomic_or(&state[BIN_TOO_MANY_LEVELS], 1);
    level[i] = lv;
  }
  levels[l] = lv;
  barrier(CLK_LOCAL_MEM_FENCE);
  if (l == 0) {
    int count[PDMESH_GRID_LEVELS];
    for (int k = 0; k < PDMESH_GRID_LEVELS; ++k) count[k] = 0;
    int top = -1;
    for (int k = 0; k < WG_SIZE; ++k) {
      const int v = levels[k];
      if (v < 0) continue;
      ++count[v];
      top = max(top, v);
    }
    bin_add_levels(count, top, state);
  }
}
#endif

// One work-item: grid L (a level with nodes) gets 2^k buckets, 2^k >= its members / 2, at
// grid_bucket_offset[L]; levels without nodes get no grid (mask -1: no node scans them). Cell size
// R_min 2^L, as the reference.
__kernel __attribute__((reqd_work_group_size(WG_SIZE, 1, 1))) void bin_plan(
    const int n, const int groups, const uint bucket_capacity, const uint member_capacity, __global const REAL* partial,
    __global int* state, __global int* grid_mask, __global uint* grid_bucket_offset, __global REAL* grid_inv_cell) {
  if (get_global_id(0) != 0 || state[BIN_FIRST_INVALID] < n || state[BIN_TOO_MANY_LEVELS]) return;
  const REAL r_min = partial[groups];
  const int top = state[BIN_TOP];
  ulong cumulative = 0, buckets = 0, members = 0;
  for (int L = 0; L < PDMESH_GRID_LEVELS; ++L) {
    const uint c = (uint)state[BIN_LEVEL_COUNT + L];
    cumulative += c;
    if (L > top || c == 0) {
      grid_mask[L] = -1;
      grid_bucket_offset[L] = 0;
      grid_inv_cell[L] = (REAL)0;
      continue;
    }
    ulong b = 1;
    while (2 * b < cumulative) b *= 2;
    grid_mask[L] = (int)(b - 1);
    grid_bucket_offset[L] = (uint)buckets;
    grid_inv_cell[L] = (REAL)1 / ldexp(r_min, L);
    buckets += b;
    members += cumulative;
  }
  const ulong big = 0x7FFFFFFFUL;  // reported sizes are ints
  state[BIN_BUCKETS] = (int)min(buckets, big);
  state[BIN_MEMBERS] = (int)min(members, big);
  state[BIN_TOO_SMALL] = buckets > (ulong)bucket_capacity || members > (ulong)member_capacity ? 1 : 0;
}

#if PDMESH_FORCE_LOOP_VECTOR
// The CPU shape counts and fills per level and work-group, in work-item 0 alone: no barriers (PoCL
// runs a group's work-items as one loop per region between barriers), and the buckets of the group's
// nodes are computed 8 at a time in explicit vectors (bin_group_buckets). The group's nodes take their
// slots bucket by bucket (bin_group_take): the first node not yet placed names a bucket, a compare of
// all the group's buckets with it (8 at a time) finds that bucket's nodes, and one atomic_add takes
// their slots; after BIN_GROUP_BUCKETS buckets the nodes left (a fine level, whose nodes fall in many
// buckets) take one slot each. A global atomic per node and level on the few buckets of a coarse grid
// would have the CPU device's threads pass those cache lines back and forth. Within a bucket the order
// is the group's (ascending nodes, groups in the atomics' order): the rows the gather makes are sorted.
#if WG_SIZE > 64 || WG_SIZE % 8 != 0
#error "the CPU shape's binning takes work-groups of at most 64 work-items, a multiple of 8 (one ulong of lanes)"
#endif
#define BIN_GROUP_BUCKETS 8
#define BIN_NO_BUCKET 0xFFFFFFFFU
// The lanes k < WG_SIZE of b holding v, as bits (bit k: b[k] == v).
ulong bin_lanes_equal(const uint* b, const uint v) {
  ulong bits = 0;
  for (int c = 0; c < WG_SIZE / 8; ++c) {
    const int8 e = vload8(c, b) == (uint8)(v);  // -1 where equal
#if defined(PACK_MASK_BITS)
    bits |= (ulong)(uchar)__builtin_ia32_cvtd2mask256(__builtin_astype(e, pack_v8si)) << (8 * c);
#else
    const int8 w = e & (int8)(1, 2, 4, 8, 16, 32, 64, 128);
    bits |= (ulong)(uint)(w.s0 | w.s1 | w.s2 | w.s3 | w.s4 | w.s5 | w.s6 | w.s7) << (8 * c);
#endif
  }
  return bits;
}

// The lowest set bit's index of a non-zero bits.
int bin_lowest_lane(const ulong bits) { return (int)popcount((bits & (0UL - bits)) - 1UL); }

// Takes the slots of the group's nodes i0 + k in their buckets b[k] (BIN_NO_BUCKET: none) and, where
// grid_nodes is given (bin_fill), writes node | tag[k] into each; without it (bin_count) only counts.
void bin_group_take(const int i0, const uint* b, const uint* tag, __global volatile uint* bucket,
                    __global int* grid_nodes) {
  const ulong lanes = WG_SIZE == 64 ? ~0UL : (1UL << WG_SIZE) - 1UL;
  ulong left = ~bin_lanes_equal(b, BIN_NO_BUCKET) & lanes;
  for (int round = 0; left && round < BIN_GROUP_BUCKETS; ++round) {
    const uint v = b[bin_lowest_lane(left)];
    ulong same = bin_lanes_equal(b, v);
    left &= ~same;
    uint s = atomic_add(&bucket[v], (uint)popcount(same));
    if (grid_nodes)
      for (; same; same &= same - 1UL) {
        const int k = bin_lowest_lane(same);
        grid_nodes[s++] = (int)((uint)(i0 + k) | tag[k]);
      }
  }
  for (; left; left &= left - 1UL) {
    const int k = bin_lowest_lane(left);
    const uint s = atomic_inc(&bucket[b[k]]);
    if (grid_nodes) grid_nodes[s] = (int)((uint)(i0 + k) | tag[k]);
  }
}

#if PDMESH_DOUBLE
#define BIN_REAL8 double8
#define BIN_REAL16 double16
#define BIN_CONVERT_REAL8 convert_double8
#else
#define BIN_REAL8 float8
#define BIN_REAL16 float16
#define BIN_CONVERT_REAL8 convert_float8
#endif
// nb_cell_coord (CPU shape) for 8 values: the same expressions lane by lane (a conversion to long
// truncates, one to REAL rounds to nearest, as the scalar casts), so the same integers.
long8 bin_cell_coord8(const BIN_REAL8 v, const REAL inv_cell) {
  const BIN_REAL8 c = clamp(v * inv_cell, -REAL_C(4.0e18), REAL_C(4.0e18));
  const long8 t = convert_long8(c);
  return t + convert_long8(BIN_CONVERT_REAL8(t) > c);  // a true compare is -1
}

// The buckets (and, where tag is given, the cell tags) of the group's nodes i0 + k (k < count) in
// grid L; BIN_NO_BUCKET for the nodes without one there (their level is above L) and past count.
// Eight nodes at a time in vectors (nb_tag's and nb_bucket's integer expressions lane by lane: the
// same values); the group's last, partial chunk by the scalar functions.
void bin_group_buckets(const int i0, const int count, const int L, __global const REAL2* xy, __global const int* level,
                       __global const int* grid_mask, __global const uint* grid_bucket_offset,
                       __global const REAL* grid_inv_cell, uint* b, uint* tag) {
  const REAL inv_cell = grid_inv_cell[L];
  const ulong mask = (ulong)grid_mask[L];
  const uint offset = grid_bucket_offset[L];
  for (int k0 = 0; k0 < WG_SIZE; k0 += 8) {
    if (k0 + 8 <= count) {
      const BIN_REAL16 v = vload16(0, (__global const REAL*)(xy + i0 + k0));  // x, y interleaved
      const ulong8 cx = as_ulong8(bin_cell_coord8(v.even, inv_cell));
      const ulong8 cy = as_ulong8(bin_cell_coord8(v.odd, inv_cell));
      if (tag) {
        const ulong8 t = cx * 0xD6E8FEB86659FD93UL + cy * 0xA0761D6478BD642FUL;
        vstore8(convert_uint8(t >> (ulong)(32 + GRID_NODE_BITS)) << (uint)GRID_NODE_BITS, 0, tag + k0);
      }
      ulong8 h = ((cx >> 2UL) * 0x9E3779B97F4A7C15UL) ^ (cy >> 2UL);
      h ^= h >> 30UL;
      h *= 0xBF58476D1CE4E5B9UL;
      h ^= h >> 27UL;
      h *= 0x94D049BB133111EBUL;
      h ^= h >> 31UL;
      const uint8 bk = convert_uint8(((h << 4UL) | ((cy & 3UL) << 2UL) | (cx & 3UL)) & mask) + offset;
      const int8 lv = vload8(0, level + i0 + k0);
      vstore8(select((uint8)(BIN_NO_BUCKET), bk, lv <= (int8)(L)), 0, b + k0);
      continue;
    }
    for (int k = k0; k < min(k0 + 8, WG_SIZE); ++k) {
      b[k] = BIN_NO_BUCKET;
      if (k >= count || level[i0 + k] > L) continue;
      const REAL2 p = xy[i0 + k];
      const long cx = nb_cell_coord(p.x, inv_cell), cy = nb_cell_coord(p.y, inv_cell);
      if (tag) tag[k] = nb_tag(cx, cy);
      b[k] = offset + nb_bucket(cx, cy, mask);
    }
  }
}

// The group's first node, its node count and its finest level (-1: nothing to bin).
int bin_group_range(const int n, __global const int* level, __global const int* state, int* i0, int* count) {
  *i0 = (int)get_group_id(0) * WG_SIZE;
  *count = min(WG_SIZE, n - *i0);
  if (get_local_id(0) != 0 || *count <= 0 || !bin_ok(state, n)) return -1;
  int first = PDMESH_GRID_LEVELS;
  for (int k = 0; k < *count; ++k) first = min(first, level[*i0 + k]);
  return first;
}

// Each node in the grid of every level from its own up to the top (the cumulative grids).
__kernel __attribute__((reqd_work_group_size(WG_SIZE, 1, 1))) void bin_count(
    const int n, __global const REAL2* xy, __global const int* level, __global const int* state,
    __global const int* grid_mask, __global const uint* grid_bucket_offset, __global const REAL* grid_inv_cell,
    __global volatile uint* bucket) {
  int i0, count;
  const int first = bin_group_range(n, level, state, &i0, &count);
  if (first < 0) return;
  const int top = state[BIN_TOP];
  uint b[WG_SIZE];
  for (int L = first; L <= top; ++L) {
    if (grid_mask[L] < 0) continue;  // a level without a grid
    bin_group_buckets(i0, count, L, xy, level, grid_mask, grid_bucket_offset, grid_inv_cell, b, 0);
    bin_group_take(i0, b, 0, bucket, 0);
  }
}
#else
// Each node in the grid of every level from its own up to the top (the cumulative grids).
__kernel __attribute__((reqd_work_group_size(WG_SIZE, 1, 1))) void bin_count(
    const int n, __global const REAL2* xy, __global const int* level, __global const int* state,
    __global const int* grid_mask, __global const uint* grid_bucket_offset, __global const REAL* grid_inv_cell,
    __global volatile uint* bucket) {
  const int i = get_global_id(0);
  if (i >= n || !bin_ok(state, n)) return;
  const REAL xi = xy[i].x, yi = xy[i].y;
  const int top = state[BIN_TOP];
  uint tag;
  for (int L = level[i]; L <= top; ++L)
    if (grid_mask[L] >= 0)
      atomic_inc(&bucket[bin_bucket(xi, yi, L, grid_mask, grid_bucket_offset, grid_inv_cell, &tag)]);
}

#endif

// Inclusive prefix sum of v over the work-group (every work-item of the group must call it). Used
// here and by the row offsets (neighbours.cl). The CPU shape sums in one work-item: PoCL runs a
// group's work-items as a loop per region between barriers, and Hillis-Steele's 13 regions cost
// more than the 64 additions. Either way the sums are exact integers, the same.
ulong group_inclusive_scan(const ulong v, __local ulong* tmp) {
  const int l = get_local_id(0);
  tmp[l] = v;
  barrier(CLK_LOCAL_MEM_FENCE);
#if PDMESH_FORCE_LOOP_VECTOR
  if (l == 0) {
    ulong s = 0;
    for (int k = 0; k < WG_SIZE; ++k) {
      s += tmp[k];
      tmp[k] = s;
    }
  }
  barrier(CLK_LOCAL_MEM_FENCE);
#else
  for (int d = 1; d < WG_SIZE; d <<= 1) {
    const ulong add = l >= d ? tmp[l - d] : 0;
    barrier(CLK_LOCAL_MEM_FENCE);
    tmp[l] += add;
    barrier(CLK_LOCAL_MEM_FENCE);
  }
#endif
  return tmp[l];
}

// Exclusive prefix sum of bucket[0 .. m) in place, per work-group, the group totals to block_total.
#if PDMESH_FORCE_LOOP_VECTOR
// The CPU shape sums the group's buckets in work-item 0, without barriers (group_inclusive_scan's
// two cost PoCL a loop over the group's work-items each): the same integer sums.
__kernel __attribute__((reqd_work_group_size(WG_SIZE, 1, 1))) void bucket_scan(const uint m, __global uint* bucket,
                                                                               __global ulong* block_total) {
  if (get_local_id(0) != 0) return;
  const uint i0 = (uint)get_group_id(0) * WG_SIZE, end = min(i0 + WG_SIZE, m);
  ulong s = 0;
  for (uint i = i0; i < end; ++i) {
    const ulong v = bucket[i];
    bucket[i] = (uint)s;
    s += v;
  }
  block_total[get_group_id(0)] = s;
}
#else
__kernel __attribute__((reqd_work_group_size(WG_SIZE, 1, 1))) void bucket_scan(const uint m, __global uint* bucket,
                                                                               __global ulong* block_total) {
  __local ulong tmp[WG_SIZE];
  const uint i = get_global_id(0);
  const ulong v = i < m ? bucket[i] : 0;
  const ulong s = group_inclusive_scan(v, tmp);
  if (i < m) bucket[i] = (uint)(s - v);
  if (get_local_id(0) == WG_SIZE - 1) block_total[get_group_id(0)] = s;
}
#endif

__kernel __attribute__((reqd_work_group_size(WG_SIZE, 1, 1))) void bucket_offsets_add(
    const uint m, __global uint* bucket, __global const ulong* block_total) {
  const uint i = get_global_id(0);
  if (i < m) bucket[i] += (uint)block_total[get_group_id(0)];
}

#if PDMESH_FORCE_LOOP_VECTOR
// bin_fill, CPU shape: the slots per level and work-group as bin_count takes its counts.
__kernel __attribute__((reqd_work_group_size(WG_SIZE, 1, 1))) void bin_fill(
    const int n, __global const REAL2* xy, __global const int* level, __global const int* state,
    __global const int* grid_mask, __global const uint* grid_bucket_offset, __global const REAL* grid_inv_cell,
    __global volatile uint* bucket, __global int* grid_nodes) {
  int i0, count;
  const int first = bin_group_range(n, level, state, &i0, &count);
  if (first < 0) return;
  const int top = state[BIN_TOP];
  uint b[WG_SIZE], tag[WG_SIZE];
  for (int L = first; L <= top; ++L) {
    if (grid_mask[L] < 0) continue;
    bin_group_buckets(i0, count, L, xy, level, grid_mask, grid_bucket_offset, grid_inv_cell, b, tag);
    bin_group_take(i0, b, tag, bucket, grid_nodes);
  }
}
#else
__kernel __attribute__((reqd_work_group_size(WG_SIZE, 1, 1))) void bin_fill(
    const int n, __global const REAL2* xy, __global const int* level, __global const int* state,
    __global const int* grid_mask, __global const uint* grid_bucket_offset, __global const REAL* grid_inv_cell,
    __global volatile uint* bucket, __global int* grid_nodes) {
  const int i = get_global_id(0);
  if (i >= n || !bin_ok(state, n)) return;
  const REAL xi = xy[i].x, yi = xy[i].y;
  const int top = state[BIN_TOP];
  uint tag;
  for (int L = level[i]; L <= top; ++L)
    if (grid_mask[L] >= 0) {
      const uint b = bin_bucket(xi, yi, L, grid_mask, grid_bucket_offset, grid_inv_cell, &tag);
      grid_nodes[atomic_inc(&bucket[b])] = (int)((uint)i | tag);
    }
}
#endif
