// Steps 2 and 3 on the device (mirror of host/sim/reference/forces.cpp, compute_forces): the net
// Lennard-Jones force of eq. 5.11 gathered per node over its padded neighbour row, the tangential
// projection for boundary nodes, and r0 (eq. 5.3). Two shapes of the same loop, one chosen by the
// program builder from the device type (host/opencl/step_program.cpp, docs/opencl.md "Force loop"):
// PDMESH_FORCE_LOOP_VECTOR walks the row 8 entries at a time in vector types (PoCL's CPU device does not
// vectorize these loops across work-items; explicit vectors give AVX code);
// PDMESH_FORCE_LOOP_SCALAR takes one entry at a time in scalar code, which a GPU compiler keeps in few
// registers (the 8-wide double vectors cost 16 registers each: 254 VGPRs on gfx90a). Both compute the
// reference's expressions in its summation order, so in double they agree with it, and each other, bit
// for bit. One division (1/r^2), one sqrt and no pow/length per entry (the vector shape: per entry
// within the cut-off only, after packing them).
#pragma OPENCL FP_CONTRACT OFF

#if PDMESH_FORCE_LOOP_VECTOR == PDMESH_FORCE_LOOP_SCALAR
#error \
    "exactly one of PDMESH_FORCE_LOOP_VECTOR and PDMESH_FORCE_LOOP_SCALAR must be 1 (the program builder defines both)"
#endif

// node_forces: net force and r0 of node i over row entries [base, base + stride), of which the first
// `count` are valid. rc2 >= 0: interior rows are a Verlet list and only entries with r^2 <= rc2 count
// (the reference's exact cut-off test); rc2 < 0: every row entry counts. count = 0 (fixed or padding
// work-items) gives F = 0, r0 = 0, no stiffness. Outputs: the force (tangential for boundary nodes),
// r0, the stability bound on dt^2 (INFINITY without one), the coincident entries and, for interior
// nodes, the entries within the cut-off. Both shapes below compute the reference's expressions per
// entry in its summation order (row order), so double results match it bit for bit.
#if PDMESH_FORCE_LOOP_VECTOR

#if PDMESH_DOUBLE
#define REAL8 double8
#define MASK8 long8  // what comparing two REAL8 gives
#define CONVERT_MASK8 convert_long8
#else
#define REAL8 float8
#define MASK8 int8
#define CONVERT_MASK8 convert_int8
#endif
#define GATHER8(a, j) (REAL8)(a[j.s0], a[j.s1], a[j.s2], a[j.s3], a[j.s4], a[j.s5], a[j.s6], a[j.s7])
// The positions of eight nodes from the packed array xy (x, y interleaved): one 16-byte load per
// entry fetches both coordinates, from one cache line, instead of a gather from each of two arrays.
// On x86 with AVX-512 in double (PoCL's CPU device on such a machine): two gather instructions, of
// the x and the y of the eight entries (byte offsets 16 j and 16 j + 8; PoCL's CPU memory is flat, so
// the global pointer passes as an address); the same values, step 1.43-1.48 -> 1.37-1.41 ms per
// iteration on 30P30N's curves with momentum (pdmesh bench, six runs each).
#if defined(__x86_64__) && defined(__AVX512F__) && PDMESH_DOUBLE
typedef int gather_v8si __attribute__((vector_size(32)));
typedef double gather_v8df __attribute__((vector_size(64)));
#define GATHER8_XY(xy, j, px, py)                                                                                  \
  {                                                                                                                \
    const gather_v8si j2 = __builtin_astype((j)*2, gather_v8si);                                                   \
    const gather_v8df none = {0, 0, 0, 0, 0, 0, 0, 0};                                                             \
    px = __builtin_astype(__builtin_ia32_gathersiv8df(none, (const void*)(ulong)(xy), j2, (uchar)0xFF, 8), REAL8); \
    py = __builtin_astype(__builtin_ia32_gathersiv8df(none, (const void*)((ulong)(xy) + 8), j2, (uchar)0xFF, 8),   \
                          REAL8);                                                                                  \
  }
#else
#define GATHER8_XY(xy, j, px, py)                                                                         \
  {                                                                                                       \
    const REAL2 p0 = xy[j.s0], p1 = xy[j.s1], p2 = xy[j.s2], p3 = xy[j.s3], p4 = xy[j.s4], p5 = xy[j.s5], \
                p6 = xy[j.s6], p7 = xy[j.s7];                                                             \
    px = (REAL8)(p0.x, p1.x, p2.x, p3.x, p4.x, p5.x, p6.x, p7.x);                                         \
    py = (REAL8)(p0.y, p1.y, p2.y, p3.y, p4.y, p5.y, p6.y, p7.y);                                         \
  }
#endif
// Components in order: sums over a row add its entries in index order, as the reference does.
#define ADD8_IN_ORDER(sum, v) sum = (((((((sum + v.s0) + v.s1) + v.s2) + v.s3) + v.s4) + v.s5) + v.s6) + v.s7
#define COUNT8(m) (-((m).s0 + (m).s1 + (m).s2 + (m).s3 + (m).s4 + (m).s5 + (m).s6 + (m).s7))

// Entries k0 .. k0 + 7 of a row as node indices; entries at or past `count` (padding, -1) become i.
int8 row_chunk(const int i, const int stride, const int count, const long base, const int k0, __global const int* index,
               int8* valid_out) {
  const int8 k = (int8)(k0) + (int8)(0, 1, 2, 3, 4, 5, 6, 7);
  const int8 valid = k < (int8)(count);
  int8 raw;
  if (k0 + 8 <= stride) {
    raw = vload8(0, index + base + k0);
  } else {  // a last, partial chunk (stride not a multiple of 8): only entries inside the row
    raw = (int8)(i);
    for (int c = 0; k0 + c < stride; ++c) ((int*)&raw)[c] = index[base + k0 + c];
  }
  *valid_out = valid;
  return select((int8)(i), raw, valid);
}

// Chunk k0 of the row: node indices (*j_out), offsets from (xi, yi) and squared distances; returns
// the mask of the entries that count (inside the row and, where `filter` is set, within rc2).
MASK8 row_chunk_offsets(const int i, const int stride, const int count, const long base, const int k0, const REAL xi,
                        const REAL yi, const MASK8 filter, const REAL rc2, __global const REAL2* xy,
                        __global const int* index, int8* j_out, REAL8* dx_out, REAL8* dy_out, REAL8* r2_out) {
  int8 valid_i;
  const int8 j = row_chunk(i, stride, count, base, k0, index, &valid_i);
  REAL8 px, py;
  GATHER8_XY(xy, j, px, py);
  const REAL8 dx = px - (REAL8)(xi), dy = py - (REAL8)(yi);
  const REAL8 r2 = dx * dx + dy * dy;
  *j_out = j;
  *dx_out = dx;
  *dy_out = dy;
  *r2_out = r2;
  return CONVERT_MASK8(valid_i) & (~filter | (r2 <= (REAL8)(rc2)));
}

// The entries of a row that count (in range and r^2 > 0), packed in row order into a private buffer
// of PACK_CAP: the Verlet rows hold ~2.4 entries per entry within the cut-off (the skin), and the
// division, square root and LJ arithmetic run on dense chunks of packed entries only. Packing keeps
// the row order, and a dropped entry added +0 before, which leaves a sum that starts at +0 unchanged,
// so the sums are the reference's bit for bit. The r0 pass reads the buffer when the whole row's
// entries fitted; a longer row (the StepBackend's unfiltered rows can be hundreds long) has its
// chunks computed as they fill and r0 from a second walk of the row.
#define PACK_CAP 64

// PACK8 appends a chunk's entries that are used (`use`: MASK8, -1 or 0 per entry) to the buffer, in
// order. On x86 with AVX-512 (PoCL's CPU device on such a machine) a compress instruction per array does
// it (the clang builtins behind _mm512_maskz_compress_pd; one store of 8, the slots past the used ones
// are spare); elsewhere (other CPUs, Oclgrind) one conditional scalar append per entry. Both leave the
// same entries in the same order.
#if defined(__x86_64__) && defined(__AVX512F__) && defined(__AVX512VL__) && defined(__AVX512DQ__)
typedef int pack_v8si __attribute__((vector_size(32)));
#if PDMESH_DOUBLE
typedef double pack_v8real __attribute__((vector_size(64)));
typedef long pack_v8mask __attribute__((vector_size(64)));
#define PACK_MASK_BITS(m) __builtin_ia32_cvtq2mask512(__builtin_astype(m, pack_v8mask))
#define PACK_COMPRESS_REAL __builtin_ia32_compressdf512_mask
#else
typedef float pack_v8real __attribute__((vector_size(32)));
typedef int pack_v8mask __attribute__((vector_size(32)));
#define PACK_MASK_BITS(m) __builtin_ia32_cvtd2mask256(__builtin_astype(m, pack_v8mask))
#define PACK_COMPRESS_REAL __builtin_ia32_compresssf256_mask
#endif
#define PACK_REAL(v, bits)                                                                                          \
  __builtin_astype(PACK_COMPRESS_REAL(__builtin_astype(v, pack_v8real), __builtin_astype(zero, pack_v8real), bits), \
                   REAL8)
#define PACK8                                                                                                 \
  {                                                                                                           \
    const uchar bits = (uchar)PACK_MASK_BITS(use);                                                            \
    vstore8(__builtin_astype(__builtin_ia32_compresssi256_mask(__builtin_astype(j, pack_v8si),                \
                                                               __builtin_astype((int8)(0), pack_v8si), bits), \
                             int8),                                                                           \
            0, pj + packed);                                                                                  \
    vstore8(PACK_REAL(dx, bits), 0, pdx + packed);                                                            \
    vstore8(PACK_REAL(dy, bits), 0, pdy + packed);                                                            \
    vstore8(PACK_REAL(r2, bits), 0, pr2 + packed);                                                            \
    packed += (int)popcount((uint)bits);                                                                      \
  }
#else
#define PACK1(c)         \
  pj[packed] = j.s##c;   \
  pdx[packed] = dx.s##c; \
  pdy[packed] = dy.s##c; \
  pr2[packed] = r2.s##c; \
  packed -= (int)use.s##c;
#define PACK8 PACK1(0) PACK1(1) PACK1(2) PACK1(3) PACK1(4) PACK1(5) PACK1(6) PACK1(7)
#endif

// The LJ force and the stability bound's pair stiffness of eight packed entries, added in entry order
// to *fx, *fy, *stiffness; entries outside `use` add +0.
void lj_chunk(const int8 j, const REAL8 dx, const REAL8 dy, const REAL8 r2, const MASK8 use, const REAL qi,
              const REAL lj_a, __global const REAL* q, REAL* fx, REAL* fy, REAL* stiffness) {
  const REAL8 zero = (REAL8)((REAL)0), one = (REAL8)((REAL)1);
  const REAL8 inv_r2 = one / select(one, r2, use);
  const REAL8 inv_r = sqrt(inv_r2);
  const REAL8 sigma = REAL_C(0.5) * ((REAL8)(qi) + GATHER8(q, j));
  const REAL8 s2 = sigma * sigma * inv_r2;
  const REAL8 s6 = s2 * s2 * s2;
  const REAL8 f = (REAL8)((REAL)-4 * lj_a) * sigma * (s6 * s6 - s6) * inv_r;
  const REAL8 cx = select(zero, f * dx, use), cy = select(zero, f * dy, use);
  ADD8_IN_ORDER(*fx, cx);
  ADD8_IN_ORDER(*fy, cy);
  // The stability bound's pair stiffness max(|df/dr|, |f|/r) (reference::lj_pair_stiffness).
  const REAL8 scale = (REAL8)((REAL)4 * lj_a) * sigma * inv_r;
  const REAL8 radial = fabs(scale * ((REAL)12 * s6 * s6 - (REAL)6 * s6));
  const REAL8 transverse = fabs(scale * (s6 * s6 - s6));
  const REAL8 cs = select(zero, select(transverse, radial, radial > transverse), use);
  ADD8_IN_ORDER(*stiffness, cs);
}

// Packed entries k .. k + 7 of the arrays J, DX, DY, R2 (private or local), of which the first `valid`
// count (pk_use); the others may be stale or unwritten slots: their node index becomes i, so the gather
// of q stays inside the arrays.
#define PACKED_CHUNK(k, valid, J, DX, DY, R2)                               \
  const int8 pk_valid = (int8)(0, 1, 2, 3, 4, 5, 6, 7) < (int8)(valid);     \
  const int8 pk_j = select((int8)(i), vload8(0, (J) + (k)), pk_valid);      \
  const REAL8 pk_dx = vload8(0, (DX) + (k)), pk_dy = vload8(0, (DY) + (k)); \
  const REAL8 pk_r2 = vload8(0, (R2) + (k));                                \
  const MASK8 pk_use = CONVERT_MASK8(pk_valid)

// r0's pass over `packed` entries of DX, DY, R2: each lane's least r^2 (best2) among the entries in the
// direction of the force (fx, fy), or in any direction (`any_direction`), and the lanes that saw one
// (found); J gives PACKED_CHUNK its node indices, which r0 does not read.
#define R0_CHUNKS(packed, J, DX, DY, R2)                                                        \
  for (int k = 0; k < (packed); k += 8) {                                                       \
    PACKED_CHUNK(k, (packed)-k, J, DX, DY, R2);                                                 \
    const MASK8 ok = pk_use & (any_direction | ((REAL8)(fx)*pk_dx + (REAL8)(fy)*pk_dy > zero)); \
    best2 = select(best2, pk_r2, ok & (pk_r2 < best2));                                         \
    found |= ok;                                                                                \
  }

// One chunk of 8 row entries from k0: their indices, offsets and r^2 (j, dx, dy, r2), the within and
// coincident counts, and the entries that count (in range, r^2 > 0) packed after `packed` (PACK8).
#define SCAN_CHUNK(k0)                                                                                    \
  int8 j;                                                                                                 \
  REAL8 dx, dy, r2;                                                                                       \
  const MASK8 in_range =                                                                                  \
      row_chunk_offsets(i, stride, count, base, (k0), xi, yi, filter, rc2, xy, index, &j, &dx, &dy, &r2); \
  within += (int)COUNT8(in_range);                                                                        \
  coincident += (int)COUNT8(in_range & (r2 == zero));                                                     \
  const MASK8 use = in_range & (r2 > zero);                                                               \
  PACK8

// r0 from each lane's least r^2 among the entries that count (`found`: lanes that saw one): the lanes'
// minimum, then its square root; 0 when no entry counted. An entry found with r^2 = INFINITY (overflow)
// gives r0 = INFINITY, as in the reference. The lanes hold r^2 > 0 or INFINITY only (the masks admit
// r^2 > 0: no NaN, no zero), so the minimum is the same value in any order: a tree of three steps
// (halves, quarters, pair) rather than a chain of seven dependent compares, which the r0 phase waits on.
// r0_squared_of_lanes: the same minimum without the square root, -1 when no entry counted.
REAL r0_squared_of_lanes(const REAL8 best2, const MASK8 found) {
  const __typeof__(best2.lo) m4 = select(best2.lo, best2.hi, best2.hi < best2.lo);
  const REAL2 m2 = select(m4.lo, m4.hi, m4.hi < m4.lo);
  const REAL b = m2.y < m2.x ? m2.y : m2.x;
#if defined(PACK_MASK_BITS)
  const int any_found = (uchar)PACK_MASK_BITS(found) != 0;  // one mask test, not a chain of extracts
#else
  const int any_found = any(found);
#endif
  return any_found ? b : (REAL)-1;
}
REAL r0_of_lanes(const REAL8 best2, const MASK8 found) {
  const REAL b = r0_squared_of_lanes(best2, found);
  return b >= (REAL)0 ? sqrt(b) : (REAL)0;
}

// node_forces, vector shape: eight row entries at a time through the packing buffer, only as many
// chunks as the row needs (boundary rows: one).
void node_forces(const int i, const int stride, const int count, const long base, const REAL xi, const REAL yi,
                 const REAL qi, const int kind_i, const REAL rc2, const REAL tx, const REAL ty, const REAL lj_a,
                 const int r0_any_direction, const REAL stability_factor, __global const REAL2* xy,
                 __global const REAL* q, __global const int* index, REAL* fx_out, REAL* fy_out, REAL* r0_out,
                 REAL* dt2_limit_out, int* coincident_out, int* within_out) {
  const MASK8 filter = (MASK8)(kind_i == 2 && rc2 >= (REAL)0 ? -1 : 0);
  const REAL8 zero = (REAL8)((REAL)0);
  // 8 spare slots: a chunk's packing writes all 8 components, past the last used one too.
  int pj[PACK_CAP + 8];
  REAL pdx[PACK_CAP + 8], pdy[PACK_CAP + 8], pr2[PACK_CAP + 8];
  REAL fx = (REAL)0, fy = (REAL)0, stiffness = (REAL)0;
  int coincident = 0, within = 0;
  int packed = 0, done = 0, overflow = 0;  // buffer entries; of them computed; whether any were dropped
  for (int k0 = 0; k0 < count; k0 += 8) {
    SCAN_CHUNK(k0)
    if (packed - done >= 8) {
      PACKED_CHUNK(done, 8, pj, pdx, pdy, pr2);
      lj_chunk(pk_j, pk_dx, pk_dy, pk_r2, pk_use, qi, lj_a, q, &fx, &fy, &stiffness);
      done += 8;
    }
    if (packed + 8 > PACK_CAP) {  // no room for another chunk: keep the entries not yet computed only
      for (int k = done; k < packed; ++k) {
        pj[k - done] = pj[k];
        pdx[k - done] = pdx[k];
        pdy[k - done] = pdy[k];
        pr2[k - done] = pr2[k];
      }
      packed -= done;
      done = 0;
      overflow = 1;
    }
  }
  if (packed > done) {
    PACKED_CHUNK(done, packed - done, pj, pdx, pdy, pr2);
    lj_chunk(pk_j, pk_dx, pk_dy, pk_r2, pk_use, qi, lj_a, q, &fx, &fy, &stiffness);
  }
  *dt2_limit_out =
      stability_factor > (REAL)0 && stiffness > (REAL)0 ? (REAL)2 * stability_factor / stiffness : INFINITY;
  // Boundary nodes slide along their curve: keep the tangential component only.
  const REAL ft = fx * tx + fy * ty;
  fx = kind_i == 1 ? ft * tx : fx;
  fy = kind_i == 1 ? ft * ty : fy;
  const MASK8 any_direction = (MASK8)(r0_any_direction && (fx != (REAL)0 || fy != (REAL)0) ? -1 : 0);
  // r0: the smallest r^2 among the qualifying entries (a minimum: the order does not matter).
  REAL8 best2 = (REAL8)(INFINITY);
  MASK8 found = (MASK8)(0);
  if (!overflow) {  // the buffer holds every entry that counts (r^2 > 0 and in range)
    R0_CHUNKS(packed, pj, pdx, pdy, pr2)
  } else {
    for (int k0 = 0; k0 < count; k0 += 8) {
      int8 j;
      REAL8 dx, dy, r2;
      const MASK8 ok =
          row_chunk_offsets(i, stride, count, base, k0, xi, yi, filter, rc2, xy, index, &j, &dx, &dy, &r2) &
          (r2 > zero) & (any_direction | ((REAL8)(fx)*dx + (REAL8)(fy)*dy > zero));
      best2 = select(best2, r2, ok & (r2 < best2));
      found |= ok;
    }
  }
  *fx_out = fx;
  *fy_out = fy;
  *r0_out = r0_of_lanes(best2, found);
  *coincident_out = coincident;
  *within_out = kind_i == 2 ? within : 0;
}

// node_forces in three parts for device_step's CPU shape, which runs them in three phases split by
// barriers (STEP_PHASE, kernels/device_step.cl): node_forces_scan walks the row and packs the entries
// that count; node_forces_lj sums their LJ force and stiffness; node_forces_r0_squared takes r0's square
// from the final force (device_step takes the stability bound's division and r0's square root later,
// eight nodes at once). PoCL runs each phase as a loop over the group's work-items, so the dependency
// chains of one node's sums (division, square root, the sums in row order) and of its r0 (which waits
// for the final force, then a minimum) overlap with the next nodes' instead of holding the core
// while the next node's row waits behind them. A node's packed entries cross the barriers in
// local memory, at most SPLIT_PACK of them (the settled lattice has ~6 within the cut-off; a boundary
// row has at most 8); a node with more gets node_forces whole in the scan's phase. With device_step's
// partial sums the group's local memory is 32,512 bytes in double at 64 work-items: within the
// 32 KiB every OpenCL device offers (Oclgrind's size), so a larger SPLIT_PACK needs a smaller group.
// The LJ part adds the packed entries in row order, unused lanes adding +0, as node_forces does, and
// r0's square is the same minimum: with node_forces' division and square root the results are
// node_forces' bit for bit.
#define SPLIT_PACK 16

// Returns the packed count (<= SPLIT_PACK: its entries written to lj, ldx, ldy, lr2, the coincident
// and within counts to the outputs) or -1 when node_forces ran whole (every output written).
int node_forces_scan(const int i, const int stride, const int count, const long base, const REAL xi, const REAL yi,
                     const REAL qi, const int kind_i, const REAL rc2, const REAL tx, const REAL ty, const REAL lj_a,
                     const int r0_any_direction, const REAL stability_factor, __global const REAL2* xy,
                     __global const REAL* q, __global const int* index, __local int* lj, __local REAL* ldx,
                     __local REAL* ldy, __local REAL* lr2, REAL* fx_out, REAL* fy_out, REAL* r0_out,
                     REAL* dt2_limit_out, int* coincident_out, int* within_out) {
  const MASK8 filter = (MASK8)(kind_i == 2 && rc2 >= (REAL)0 ? -1 : 0);
  const REAL8 zero = (REAL8)((REAL)0);
  // 8 spare slots: a chunk's packing writes all 8 components, past the last used one too.
  int pj[SPLIT_PACK + 8];
  REAL pdx[SPLIT_PACK + 8], pdy[SPLIT_PACK + 8], pr2[SPLIT_PACK + 8];
  int coincident = 0, within = 0, packed = 0;
  for (int k0 = 0; k0 < count; k0 += 8) {
    SCAN_CHUNK(k0)
    if (packed > SPLIT_PACK) {
      node_forces(i, stride, count, base, xi, yi, qi, kind_i, rc2, tx, ty, lj_a, r0_any_direction, stability_factor, xy,
                  q, index, fx_out, fy_out, r0_out, dt2_limit_out, coincident_out, within_out);
      return -1;
    }
  }
  for (int k = 0; k < packed; k += 8) {
    vstore8(vload8(0, pj + k), 0, lj + k);
    vstore8(vload8(0, pdx + k), 0, ldx + k);
    vstore8(vload8(0, pdy + k), 0, ldy + k);
    vstore8(vload8(0, pr2 + k), 0, lr2 + k);
  }
  *coincident_out = coincident;
  *within_out = kind_i == 2 ? within : 0;
  return packed;
}

// The LJ force (tangential for boundary nodes) and the summed pair stiffness of the `packed` entries
// node_forces_scan left in local memory; slots past `packed` are masked (their node index becomes i).
// device_step turns the stiffness into the stability bound for eight nodes at once (step_moves8).
void node_forces_lj(const int i, const int packed, const int kind_i, const REAL qi, const REAL tx, const REAL ty,
                    const REAL lj_a, __global const REAL* q, __local const int* lj, __local const REAL* ldx,
                    __local const REAL* ldy, __local const REAL* lr2, REAL* fx_out, REAL* fy_out, REAL* stiffness_out) {
  REAL fx = (REAL)0, fy = (REAL)0, stiffness = (REAL)0;
  for (int k = 0; k < packed; k += 8) {
    PACKED_CHUNK(k, packed - k, lj, ldx, ldy, lr2);
    lj_chunk(pk_j, pk_dx, pk_dy, pk_r2, pk_use, qi, lj_a, q, &fx, &fy, &stiffness);
  }
  *stiffness_out = stiffness;
  // Boundary nodes slide along their curve: keep the tangential component only.
  const REAL ft = fx * tx + fy * ty;
  *fx_out = kind_i == 1 ? ft * tx : fx;
  *fy_out = kind_i == 1 ? ft * ty : fy;
}

// r0 over the `packed` entries in local memory, given the node's final force (fx, fy): node_forces' r0 pass,
// without its square root: r0^2, or -1 where r0 is 0 (no entry counted). device_step takes the square
// roots of eight nodes at once (step_moves8).
REAL node_forces_r0_squared(const int i, const int packed, const REAL fx, const REAL fy, const int r0_any_direction,
                            __local const int* lj, __local const REAL* ldx, __local const REAL* ldy,
                            __local const REAL* lr2) {
  const REAL8 zero = (REAL8)((REAL)0);
  const MASK8 any_direction = (MASK8)(r0_any_direction && (fx != (REAL)0 || fy != (REAL)0) ? -1 : 0);
  REAL8 best2 = (REAL8)(INFINITY);
  MASK8 found = (MASK8)(0);
  R0_CHUNKS(packed, lj, ldx, ldy, lr2)
  return r0_squared_of_lanes(best2, found);
}

#else  // PDMESH_FORCE_LOOP_SCALAR

// Entry k of the row relative to (xi, yi): the offsets and r^2 (what both passes recompute: keeping
// them would cost registers or memory; recomputing costs three loads that hit the cache).
// Returns whether the entry counts (rc2 < 0, or r^2 within rc2 when `filter`).
int row_entry(const long base, const int k, const REAL xi, const REAL yi, const int filter, const REAL rc2,
              __global const REAL2* xy, __global const int* index, int* j_out, REAL* dx_out, REAL* dy_out,
              REAL* r2_out) {
  const int j = index[base + k];
  const REAL2 p = xy[j];  // one load: the packed array holds x and y side by side
  const REAL dx = p.x - xi, dy = p.y - yi;
  const REAL r2 = dx * dx + dy * dy;
  *j_out = j;
  *dx_out = dx;
  *dy_out = dy;
  *r2_out = r2;
  return !filter || r2 <= rc2;  // a NaN r^2 fails the filter, as in the vector shape
}

// node_forces, scalar shape: one entry at a time, no vectors, no masks: a few scalars live across the
// loop (sums, counters, the node's own values), so a GPU keeps many more work-items resident.
void node_forces(const int i, const int stride, const int count, const long base, const REAL xi, const REAL yi,
                 const REAL qi, const int kind_i, const REAL rc2, const REAL tx, const REAL ty, const REAL lj_a,
                 const int r0_any_direction, const REAL stability_factor, __global const REAL2* xy,
                 __global const REAL* q, __global const int* index, REAL* fx_out, REAL* fy_out, REAL* r0_out,
                 REAL* dt2_limit_out, int* coincident_out, int* within_out) {
  const int filter = kind_i == 2 && rc2 >= (REAL)0;
  const REAL four_a = (REAL)-4 * lj_a, four_a_pos = (REAL)4 * lj_a;
  REAL fx = (REAL)0, fy = (REAL)0, stiffness = (REAL)0;
  int coincident = 0, within = 0;
  for (int k = 0; k < count; ++k) {
    int j;
    REAL dx, dy, r2;
    if (!row_entry(base, k, xi, yi, filter, rc2, xy, index, &j, &dx, &dy, &r2)) continue;
    ++within;
    if (r2 == (REAL)0) {  // coincident: no direction, counted (the reference's rule)
      ++coincident;
      continue;
    }
    if (!(r2 > (REAL)0)) continue;  // NaN: no contribution, as the vector shape's mask
    const REAL inv_r2 = (REAL)1 / r2;
    const REAL inv_r = sqrt(inv_r2);
    const REAL sigma = REAL_C(0.5) * (qi + q[j]);
    const REAL s2 = sigma * sigma * inv_r2;
    const REAL s6 = s2 * s2 * s2;
    const REAL f = four_a * sigma * (s6 * s6 - s6) * inv_r;
    fx += f * dx;
    fy += f * dy;
    // The stability bound's pair stiffness max(|df/dr|, |f|/r) (reference::lj_pair_stiffness).
    const REAL scale = four_a_pos * sigma * inv_r;
    const REAL radial = fabs(scale * ((REAL)12 * s6 * s6 - (REAL)6 * s6));
    const REAL transverse = fabs(scale * (s6 * s6 - s6));
    stiffness += radial > transverse ? radial : transverse;
  }
  *dt2_limit_out =
      stability_factor > (REAL)0 && stiffness > (REAL)0 ? (REAL)2 * stability_factor / stiffness : INFINITY;
  // Boundary nodes slide along their curve: keep the tangential component only.
  const REAL ft = fx * tx + fy * ty;
  fx = kind_i == 1 ? ft * tx : fx;
  fy = kind_i == 1 ? ft * ty : fy;
  const int any_direction = r0_any_direction && (fx != (REAL)0 || fy != (REAL)0);
  // r0: the smallest r^2 among the qualifying entries.
  REAL best2 = INFINITY;
  int found = 0;
  for (int k = 0; k < count; ++k) {
    int j;
    REAL dx, dy, r2;
    if (!row_entry(base, k, xi, yi, filter, rc2, xy, index, &j, &dx, &dy, &r2) || !(r2 > (REAL)0)) continue;
    if (!(any_direction || fx * dx + fy * dy > (REAL)0)) continue;
    found = 1;
    best2 = r2 < best2 ? r2 : best2;
  }
  *fx_out = fx;
  *fy_out = fy;
  // An entry found with r^2 = INFINITY (overflow) gives r0 = INFINITY, as in the reference.
  *r0_out = found ? sqrt(best2) : (REAL)0;
  *coincident_out = coincident;
  *within_out = kind_i == 2 ? within : 0;
}

#endif  // PDMESH_FORCE_LOOP_VECTOR

// The StepBackend kernel: forces and r0 of every node over a list that holds exactly the neighbours,
// and the stability bound on dt^2 (INFINITY when off or without stiffness).
__kernel __attribute__((reqd_work_group_size(WG_SIZE, 1, 1))) void compute_forces(
    const int n, const int stride, const REAL lj_a, const int r0_any_direction, const REAL stability_factor,
    __global const REAL2* xy, __global const REAL* q, __global const uchar* kind, __global const REAL* tx,
    __global const REAL* ty, __global const int* count, __global const int* index, __global REAL* fx_out,
    __global REAL* fy_out, __global REAL* r0_out, __global REAL* limit_out, __global int* coincident_out) {
  const int i = get_global_id(0);
  const int active = i < n;
  const int ic = active ? i : 0;  // padding work-items read node 0 and write nothing
  const int kind_i = active ? (int)kind[ic] : 0;
  const int row = kind_i != 0 ? min(count[ic], stride) : 0;
  REAL fx, fy, r0, limit;
  int coincident, within;
  const REAL2 pi = xy[ic];
  node_forces(ic, stride, row, row_base(ic, stride), pi.x, pi.y, q[ic], kind_i, (REAL)-1, tx[ic], ty[ic], lj_a,
              r0_any_direction, stability_factor, xy, q, index, &fx, &fy, &r0, &limit, &coincident, &within);
  if (!active) return;
  limit_out[i] = kind_i != 0 ? limit : INFINITY;
  fx_out[i] = fx;
  fy_out[i] = fy;
  r0_out[i] = r0;
  coincident_out[i] = coincident;
}
