// One whole iteration for the device-resident run (host/opencl/device_simulation.cpp) in one launch:
// forces + r0 (forces.cl), local time step + move (time_step.cl), spacing update (spacing_field.cl),
// the clearance-budget filter that picks the few interior nodes the host must test exactly, the Verlet-skin
// displacement check, and per-group partial sums (reduce.cl). A second, small kernel writes back
// the positions the host's boundary handling decided.
#pragma OPENCL FP_CONTRACT OFF

// STEP_PARTIALS (sum |F|, sum kinetic, moving, pairs within, coincident | max |F|, max skin use) and the
// step counters' slots (COUNTER_CANDIDATES, COUNTER_NON_FINITE, WINDOW_HALT) come from the program
// builder (host/opencl/step_program.hpp, device_window.hpp).

// The background field's arrays, passed as one group of arguments (bg_cell: leaf_cell, 4 per leaf).
#define BG_ARGS                                                                                 \
  const REAL bg_origin_x, const REAL bg_origin_y, const REAL bg_inv_root, const int bg_grid,    \
      __global const int *bg_root, __global const int *bg_child, __global const int *bg_corner, \
      __global const int *bg_cell, __global const REAL *bg_q

// Bilinear spacing at (u, v) in a leaf: spacing_at's expression.
REAL bg_interpolate(const int leaf, const REAL u, const REAL v, __global const int* bg_corner,
                    __global const REAL* bg_q) {
  const REAL q00 = bg_q[bg_corner[4 * leaf + 0]];
  const REAL q10 = bg_q[bg_corner[4 * leaf + 1]];
  const REAL q01 = bg_q[bg_corner[4 * leaf + 2]];
  const REAL q11 = bg_q[bg_corner[4 * leaf + 3]];
  return ((REAL)1 - v) * (((REAL)1 - u) * q00 + u * q10) + v * (((REAL)1 - u) * q01 + u * q11);
}

// Spacing at (px, py); *leaf: the node's cached leaf, updated when the point left it. Inlined with
// bg_locate_cached (device_step and boundary_snap call it once per node): as a call, PoCL's work-item
// loop passes the leaf and (u, v) through memory and saves and restores registers around it.
__attribute__((always_inline)) REAL bg_spacing_cached(const REAL px, const REAL py, int* leaf, BG_ARGS) {
  REAL u, v;
  const int found = bg_locate_cached(px, py, leaf, bg_origin_x, bg_origin_y, bg_inv_root, bg_grid, bg_root, bg_child,
                                     bg_cell, &u, &v);
  return bg_interpolate(found, u, v, bg_corner, bg_q);
}
#define BG_PASS bg_origin_x, bg_origin_y, bg_inv_root, bg_grid, bg_root, bg_child, bg_corner, bg_cell, bg_q

// STEP_PHASE: where the CPU shape (PDMESH_FORCE_LOOP_VECTOR) splits device_step into phases with a
// barrier that changes nothing else (every work-item reaches it; the force phases pass each
// work-item's packed row entries through its own slice of local memory; the phases of eight nodes at
// once, step_moves8 and skin_use8, read and write the slots of their eight work-items, in local
// memory, only between two barriers). PoCL runs each region between barriers as a loop over the
// group's work-items: a node's dependency chains (the force's sums and r0: kernels/forces.cl,
// node_forces_scan) then overlap with the next node's instead of waiting behind its row scan, and the
// square roots and divisions of the time step, momentum and skin use run in vector instructions
// instead of one node after the other (docs/opencl.md, "Kernels written for PoCL's CPU device"). A GPU
// interleaves work-items in hardware: no barrier there.
#if PDMESH_FORCE_LOOP_VECTOR
#define STEP_PHASE() barrier(CLK_LOCAL_MEM_FENCE)
#else
#define STEP_PHASE()
#endif

// The two levels of a spacing lookup in spacing leaf `leaf`, prefetched (step_prefetch, step_prefetch_spacing
// and boundary.cl's snap_prefetch): the leaf's cell and corner indices, then the corner spacings the
// corner indices point to. No-ops where the prefetches do nothing (see step_prefetch).
void prefetch_leaf_lookup(const int leaf, __global const int* bg_cell, __global const int* bg_corner) {
#if PDMESH_FORCE_LOOP_VECTOR && defined(__x86_64__)
  __builtin_prefetch((const void*)(ulong)(bg_cell + 4 * leaf));
  __builtin_prefetch((const void*)(ulong)(bg_corner + 4 * leaf));
#endif
}

void prefetch_leaf_spacings(const int leaf, __global const int* bg_corner, __global const REAL* bg_q) {
#if PDMESH_FORCE_LOOP_VECTOR && defined(__x86_64__)
  const int4 c = vload4(leaf, bg_corner);
  __builtin_prefetch((const void*)(ulong)(bg_q + c.x));
  __builtin_prefetch((const void*)(ulong)(bg_q + c.y));
  __builtin_prefetch((const void*)(ulong)(bg_q + c.z));
  __builtin_prefetch((const void*)(ulong)(bg_q + c.w));
#endif
}

// step_prefetch: on a CPU (the vector shape on x86), what node a's step will read from anywhere in the
// arrays is prefetched into the cache a few work-items ahead (STEP_PREFETCH_AHEAD): the positions and
// spacings of its row entries, and its spacing leaf's cell and corners. PoCL runs a group's
// work-items one after the other on one core, and without it the force loop's gathers of xy and q
// and the spacing lookup wait for memory (docs/opencl.md, "Kernels written for PoCL's CPU device").
// A prefetch changes no value. Elsewhere (a GPU interleaves work-items in hardware) it does nothing.
// The row entries' positions and spacings only from STEP_PREFETCH_ROWS_FROM nodes on: below, the
// arrays they are gathered from (24 B per node in double) stay in the cores' caches, and the loop over
// the row costs more than it saves (docs/opencl.md).
#define STEP_PREFETCH_AHEAD 2
#define STEP_PREFETCH_ROWS_FROM 32768
void step_prefetch(const int a, const int n, __global const uchar* kind, __global const int* count,
                   __global const ulong* row_offset, __global const int* index, __global const REAL2* xy,
                   __global const REAL* q, __global const int* node_leaf, __global const int* bg_cell,
                   __global const int* bg_corner) {
#if PDMESH_FORCE_LOOP_VECTOR && defined(__x86_64__)
  if (a >= n || kind[a] == 0) return;
  if (n >= STEP_PREFETCH_ROWS_FROM) {
    const int entries = count[a];
    const long start = (long)row_offset[a];
    for (int k = 0; k < entries; ++k) {
      const int j = index[start + k];
      __builtin_prefetch((const void*)(ulong)(xy + j));
      __builtin_prefetch((const void*)(ulong)(q + j));
    }
  }
  prefetch_leaf_lookup(node_leaf[a], bg_cell, bg_corner);
#endif
}

// step_prefetch_spacing: the same for the spacing lookup's second level, in the phase that makes the
// lookups: the corner spacings bg_q of node a's leaf. Its bg_corner entries were prefetched by
// step_prefetch in the forces' phase, so reading them here rarely waits; the corner spacings are
// loaded through them and otherwise miss (the background field is larger than the caches near the
// cores). Node a's leaf is the one before its move, which a move rarely leaves.
void step_prefetch_spacing(const int a, const int n, __global const int* node_leaf, __global const int* bg_corner,
                           __global const REAL* bg_q) {
#if PDMESH_FORCE_LOOP_VECTOR && defined(__x86_64__)
  if (a >= n) return;
  prefetch_leaf_spacings(node_leaf[a], bg_corner, bg_q);
#endif
}

#if PDMESH_FORCE_LOOP_VECTOR
// The slots of device_step's local array `values` (free until the partial sums) that carry a node's
// force, r0, stability bound, state and carried move into step_moves8 (slot-major, WG_SIZE each).
// State 0: a fixed node (or padding); 1: r0 comes as r0^2 (-1 for r0 = 0: r0_squared_of_lanes) and
// the bound as the summed pair stiffness (node_forces_lj), so that step_moves8 takes the square root
// and the bound's division of eight nodes at once; 2: r0 and the bound as node_forces gave them. It
// writes |F| and the kinetic term to their partial sums' slots (0, 1 and 5) and the move to slots
// STEP_MOVE_DX, STEP_MOVE_DY, which device_step reads before it writes those partial sums.
#define STEP_MOVE_FX 0
#define STEP_MOVE_FY 1
#define STEP_MOVE_R0 2
#define STEP_MOVE_LIMIT 3
#define STEP_MOVE_STATE 4
#define STEP_MOVE_PX 5
#define STEP_MOVE_PY 6
#define STEP_MOVE_DX 2
#define STEP_MOVE_DY 3
#if STEP_PARTIALS < 7
#error "step_moves8 needs 7 slots of device_step's partial sums' array"
#endif

// Nodes v .. v + 7 of the group (v: the first one's slot 0 entry): the scalar shape's local time step
// (local_dt2), move, momentum (beta > 0; momentum_move), |F| and kinetic term, by kernels/time_step.cl's
// eight-lane functions: each lane the scalar shape's value bit for bit. Fixed nodes: all 0.
void step_moves8(__local REAL* v, const REAL dt_gm2, const REAL beta, const REAL mix, const REAL stability_factor) {
  const REAL8 zero = (REAL8)((REAL)0);
  const REAL8 fx = vload8(0, v + STEP_MOVE_FX * WG_SIZE), fy = vload8(0, v + STEP_MOVE_FY * WG_SIZE);
  const REAL8 state = vload8(0, v + STEP_MOVE_STATE * WG_SIZE);
  const MASK8 moving = state != zero, from_parts = state == (REAL8)((REAL)1);
  // State 1: r0 and the bound by r0_of_lanes' and node_forces' expressions; state 2: as they came.
  const REAL8 r0_in = vload8(0, v + STEP_MOVE_R0 * WG_SIZE), limit_in = vload8(0, v + STEP_MOVE_LIMIT * WG_SIZE);
  const REAL8 r0 = select(r0_in, select(zero, sqrt(r0_in), r0_in >= zero), from_parts);
  const MASK8 bounded = (limit_in > zero) & (MASK8)(stability_factor > (REAL)0 ? -1 : 0);
  const REAL8 limit =
      select(limit_in, select((REAL8)(INFINITY), (REAL)2 * stability_factor / limit_in, bounded), from_parts);
  const REAL8 f = force_norm8(fx, fy);
  const REAL8 dt2 = local_dt2_8(f, r0, dt_gm2, limit);
  REAL8 dx = select(zero, REAL_C(0.5) * dt2 * fx, moving), dy = select(zero, REAL_C(0.5) * dt2 * fy, moving);
  if (beta > (REAL)0) {
    REAL8 mx, my;
    momentum_move8(dx, dy, vload8(0, v + STEP_MOVE_PX * WG_SIZE), vload8(0, v + STEP_MOVE_PY * WG_SIZE), beta, mix, fx,
                   fy, r0, &mx, &my);
    dx = select(dx, mx, moving);
    dy = select(dy, my, moving);
  }
#if PDMESH_DOUBLE
  const REAL8 kinetic = REAL_C(0.125) * dt2 * (fx * fx + fy * fy);  // the reference's expression
#else
  const REAL8 kinetic = REAL_C(0.125) * dt2 * f * f;  // f^2 could overflow in float
#endif
  vstore8(select(zero, f, moving), 0, v);
  vstore8(select(zero, kinetic, moving), 0, v + WG_SIZE);
  vstore8(select(zero, f, moving), 0, v + 5 * WG_SIZE);
  vstore8(dx, 0, v + STEP_MOVE_DX * WG_SIZE);
  vstore8(dy, 0, v + STEP_MOVE_DY * WG_SIZE);
}

// The skin use of nodes s .. s + 7 from their skin_use_parts in the slots of s (stride WG_SIZE: d2,
// growth, divisor, factor): skin_use_of's expression on each lane.
REAL8 skin_use8(__local const REAL* s) {
  const REAL8 d2 = vload8(0, s), grow = vload8(0, s + WG_SIZE);
  const REAL8 divisor = vload8(0, s + 2 * WG_SIZE), factor = vload8(0, s + 3 * WG_SIZE);
  return (sqrt(d2) + grow) / divisor * factor;
}
#endif

// Inputs xy (positions, x and y interleaved), q (current), outputs xy_next, q_next. budget[i]: interior node i's
// clearance budget (host/sim/boundary_handling.hpp, clearance_budget): a move whose cost (the same move_cost formula,
// with this precision's epsilon) is below it stays inside the domain, exactly; the cost is subtracted. A spent budget
// is refreshed from the segments segs (kernels/clearance.cl) when the move is clearly inside. Other interior nodes (and
// non-finite moves) are appended to cand_index / cand_rec (x, y, dx, dy) with an integer atomic counter
// (counters[COUNTER_CANDIDATES]) for the host's exact test (counters[COUNTER_NON_FINITE]: set when a move is not
// finite); boundary nodes write (x, y, dx, dy) to their slot bslot[i] of brec. beta > 0: the move is momentum's d
// (carried: each node's previous d, x and y interleaved, turned towards F by mix > 0; any buffer when beta = 0).
// skin_use: (|x_next - x_build| + cutoff max(0, q_next - q_build)) / (skin cutoff q_build) over the share its skin
// class allows (skin_use_of), maximised per group (interior nodes the host does not touch; the host covers the rest).
__kernel __attribute__((reqd_work_group_size(WG_SIZE, 1, 1))) void device_step(
    const int n, const REAL cutoff, const REAL lj_a, const int r0_any_direction, const REAL stability_factor,
    __global const REAL* dt_gm2_in, const REAL skin_cutoff, __global const REAL2* xy, __global const REAL* q,
    __global const uchar* kind, __global const REAL* tx, __global const REAL* ty, __global const int* count,
    __global const ulong* row_offset, __global const int* index, __global const REAL2* xy_build,
    __global const REAL* q_build, __global const uchar* skin_class, __global const int* bslot, __global REAL2* xy_next,
    __global REAL* q_next, __global REAL* budget, __global int* node_leaf, __global REAL* brec,
    __global int* cand_index, __global REAL* cand_rec, __global int* counters, __global REAL* partials,
    __global const REAL* segs, const int n_segs, const REAL seg_scale, const REAL beta, const REAL mix,
    __global REAL2* carried, BG_ARGS) {
  __local REAL values[STEP_PARTIALS * WG_SIZE];
#if PDMESH_FORCE_LOOP_VECTOR
  // The packed row entries between the phases of node_forces (kernels/forces.cl, node_forces_scan),
  // and their count (-1: node_forces ran whole). The count goes through local memory too: PoCL 3.1
  // misreads a private count held across these barriers in groups that mix the two cases.
  __local int split_j[WG_SIZE * SPLIT_PACK];
  __local REAL split_dx[WG_SIZE * SPLIT_PACK], split_dy[WG_SIZE * SPLIT_PACK], split_r2[WG_SIZE * SPLIT_PACK];
  __local int split_n[WG_SIZE];
#endif
  // The window was halted for the host (kernels/window.cl): this iteration does nothing (uniform exit).
  if (counters[WINDOW_HALT] != 0) return;
  const REAL dt_gm2 = dt_gm2_in[0];  // the time-step rule's (iteration_rule or the host)
  const int i = get_global_id(0), l = get_local_id(0);
  const int active = i < n;
  // Every work-item runs the same code up to the group reduction; padding ones are masked.
  const int ic = active ? i : 0;  // padding work-items compute node 0 and write nothing
  const int kind_i = active ? (int)kind[ic] : 0;
  const int moving = kind_i != 0;
  // Row ic: count[ic] entries at index[row_offset[ic] ..] (CSR, kernels/neighbours.cl). The vector loop
  // reads whole chunks of 8 (its `stride` argument: the row rounded up to 8); the index buffer has 8
  // readable entries past the last row, and entries past the row are masked.
  const int row = moving ? count[ic] : 0;
  const long row_start = (long)row_offset[ic];
  const REAL2 pi = xy[ic];
  const REAL xi = pi.x, yi = pi.y, qi = q[ic];
  const REAL rc = cutoff * qi;
  step_prefetch(i + STEP_PREFETCH_AHEAD, n, kind, count, row_offset, index, xy, q, node_leaf, bg_cell, bg_corner);
  REAL fx, fy, r0, limit;
  int coincident, within;
#if PDMESH_FORCE_LOOP_VECTOR
  // node_forces in three phases (kernels/forces.cl, node_forces_scan): the row, the LJ sums, r0.
  split_n[l] = node_forces_scan(ic, (row + 7) & ~7, row, row_start, xi, yi, qi, kind_i, rc * rc, tx[ic], ty[ic], lj_a,
                                r0_any_direction, stability_factor, xy, q, index, split_j + SPLIT_PACK * l,
                                split_dx + SPLIT_PACK * l, split_dy + SPLIT_PACK * l, split_r2 + SPLIT_PACK * l, &fx,
                                &fy, &r0, &limit, &coincident, &within);
  STEP_PHASE();
  if (split_n[l] >= 0)
    node_forces_lj(ic, split_n[l], kind_i, qi, tx[ic], ty[ic], lj_a, q, split_j + SPLIT_PACK * l,
                   split_dx + SPLIT_PACK * l, split_dy + SPLIT_PACK * l, split_r2 + SPLIT_PACK * l, &fx, &fy,
                   &limit);  // the stiffness: step_moves8 divides
  STEP_PHASE();
  // r0 and the stability bound as node_forces gave them (split_n[l] < 0), or r0's square from the r0
  // pass and, in `limit`, node_forces_lj's summed stiffness (STEP_MOVE_STATE 1).
  const int r0_squared = split_n[l] >= 0;
  if (r0_squared)
    r0 = node_forces_r0_squared(ic, split_n[l], fx, fy, r0_any_direction, split_j + SPLIT_PACK * l,
                                split_dx + SPLIT_PACK * l, split_dy + SPLIT_PACK * l, split_r2 + SPLIT_PACK * l);
  // The local time step, the move and momentum of eight nodes at once (step_moves8), through the
  // partial sums' array: STEP_MOVE_* slots in; the move, |F| and the kinetic term out.
  values[STEP_MOVE_FX * WG_SIZE + l] = fx;
  values[STEP_MOVE_FY * WG_SIZE + l] = fy;
  values[STEP_MOVE_R0 * WG_SIZE + l] = r0;
  values[STEP_MOVE_LIMIT * WG_SIZE + l] = limit;
  values[STEP_MOVE_STATE * WG_SIZE + l] = !moving ? (REAL)0 : r0_squared ? (REAL)1 : (REAL)2;
  const REAL2 carried_i = beta > (REAL)0 && moving ? carried[i] : (REAL2)((REAL)0, (REAL)0);
  values[STEP_MOVE_PX * WG_SIZE + l] = carried_i.x;
  values[STEP_MOVE_PY * WG_SIZE + l] = carried_i.y;
  STEP_PHASE();
  if ((l & 7) == 0) step_moves8(values + l, dt_gm2, beta, mix, stability_factor);
  STEP_PHASE();
  const REAL dx = values[STEP_MOVE_DX * WG_SIZE + l], dy = values[STEP_MOVE_DY * WG_SIZE + l];
  // Node i alone reads and writes its carried move (one buffer serves). Fixed: p = 0.
  if (beta > (REAL)0 && active) carried[i] = (REAL2)(dx, dy);
#else
  node_forces(ic, (row + 7) & ~7, row, row_start, xi, yi, qi, kind_i, rc * rc, tx[ic], ty[ic], lj_a, r0_any_direction,
              stability_factor, xy, q, index, &fx, &fy, &r0, &limit, &coincident, &within);
  const REAL dt2 = local_dt2(fx, fy, r0, dt_gm2, limit);
  REAL dx = moving ? REAL_C(0.5) * dt2 * fx : (REAL)0;
  REAL dy = moving ? REAL_C(0.5) * dt2 * fy : (REAL)0;
  // Heavy-ball momentum (beta > 0 only, uniform; kernels/time_step.cl, momentum_move): node i alone
  // reads and writes its carried move, so one buffer serves (no double buffering). Fixed: p = 0.
  if (beta > (REAL)0 && active) {
    if (moving) {
      const REAL2 d = momentum_move(dx, dy, carried[i], beta, mix, fx, fy, r0);
      dx = d.x;
      dy = d.y;
    }
    carried[i] = (REAL2)(dx, dy);
  }
  const REAL f = moving ? force_norm(fx, fy) : (REAL)0;                               // reduce.cl: float-safe |F|
#if PDMESH_DOUBLE
  const REAL kinetic = moving ? REAL_C(0.125) * dt2 * (fx * fx + fy * fy) : (REAL)0;  // the reference's expression
#else
  const REAL kinetic = moving ? REAL_C(0.125) * dt2 * f * f : (REAL)0;  // f^2 could overflow in float
#endif
#endif
#if PDMESH_FORCE_LOOP_VECTOR
  REAL skin_d2 = (REAL)0, skin_grow = (REAL)0, skin_divisor = (REAL)1, skin_factor = (REAL)0;
#else
  REAL skin_use = (REAL)0;
#endif
  step_prefetch_spacing(i + STEP_PREFETCH_AHEAD, n, node_leaf, bg_corner, bg_q);
  if (active) {
    const REAL xn = xi + dx, yn = yi + dy;
    int leaf = node_leaf[i];
    const REAL qn = bg_spacing_cached(xn, yn, &leaf, BG_PASS);
    if (leaf != node_leaf[i]) node_leaf[i] = leaf;
    int host = 0;
    if (kind_i == 1) {
      const int s = bslot[i];
      brec[4 * s] = xi;
      brec[4 * s + 1] = yi;
      brec[4 * s + 2] = dx;
      brec[4 * s + 3] = dy;
      host = 1;
    } else if (kind_i == 2) {
      const REAL b = budget[i];
      const REAL ex = xn - xi, ey = yn - yi;
      const REAL cost = clearance_move_cost(ex, ey, xn, yn, b);
      // Budget spent: a node known inside (b > 0) gets a fresh one when its move is clearly inside
      // (kernels/clearance.cl); the rest go to the host's exact test. PDMESH_REFRESH_KERNEL: the
      // refresh runs in its own kernel (refresh_budgets below; its segment loop would cost this
      // kernel GPU registers): the node is listed for it as ~i.
#if PDMESH_REFRESH_KERNEL
      const REAL fresh = (REAL)0;
      const int deferred = !(cost < b) && b > (REAL)0;
#else
      const REAL fresh =
          !(cost < b) && b > (REAL)0 ? clearance_refresh(ex, ey, xn, yn, segs, n_segs, seg_scale) : (REAL)0;
      const int deferred = 0;
#endif
      if (cost < b) {  // false for NaN
        budget[i] = b - cost;
      } else if (fresh > (REAL)0) {
        budget[i] = fresh;
      } else {
        const int s = atomic_inc(&counters[COUNTER_CANDIDATES]);
        cand_index[s] = deferred ? ~i : i;
        cand_rec[4 * s] = xi;
        cand_rec[4 * s + 1] = yi;
        cand_rec[4 * s + 2] = dx;
        cand_rec[4 * s + 3] = dy;
        if (!deferred) atomic_or(&counters[COUNTER_HOST], 1);
        host = 1;  // a refreshed node's skin use: refresh_budgets
      }
    }
    xy_next[i] = (REAL2)(xn, yn);
    q_next[i] = qn;
    // A move that is not finite halts the iteration for the host (counters[COUNTER_NON_FINITE]): boundary_snap then
    // writes nothing, so the state before this step stays whole on the device.
    if (moving && !(isfinite(dx) && isfinite(dy) && isfinite(xn) && isfinite(yn)))
      atomic_or(&counters[COUNTER_NON_FINITE], 1);
#if PDMESH_FORCE_LOOP_VECTOR
    // The skin use's operands into the scratch slots of l (split_dx is free after the force phases);
    // nodes without one get operands that give +0, the scalar shape's value for them.
    if (!host && kind_i == 2)
      skin_use_parts((REAL2)(xn, yn), qn, xy_build[i], q_build[i], cutoff, skin_cutoff, skin_class[i], &skin_d2,
                     &skin_grow, &skin_divisor, &skin_factor);
#else
    if (!host && kind_i == 2)
      skin_use = skin_use_of((REAL2)(xn, yn), qn, xy_build[i], q_build[i], cutoff, skin_cutoff, skin_class[i]);
#endif
  }
#if PDMESH_FORCE_LOOP_VECTOR
  // step_moves8 wrote slots 0, 1 and 5; the skin use (slot 6) eight nodes at once after a barrier.
  split_dx[l] = skin_d2;
  split_dx[WG_SIZE + l] = skin_grow;
  split_dx[2 * WG_SIZE + l] = skin_divisor;
  split_dx[3 * WG_SIZE + l] = skin_factor;
#else
  values[l] = f;
  values[WG_SIZE + l] = kinetic;
  values[5 * WG_SIZE + l] = f;
  values[6 * WG_SIZE + l] = skin_use;
#endif
  values[2 * WG_SIZE + l] = moving ? (REAL)1 : (REAL)0;
  values[3 * WG_SIZE + l] = moving ? (REAL)within : (REAL)0;
  values[4 * WG_SIZE + l] = moving ? (REAL)coincident : (REAL)0;
#if PDMESH_FORCE_LOOP_VECTOR
  STEP_PHASE();
  if ((l & 7) == 0) vstore8(skin_use8(split_dx + l), 0, values + 6 * WG_SIZE + l);
#endif
  group_reduce(values, STEP_PARTIALS, 5);
  if (l < STEP_PARTIALS) partials[STEP_PARTIALS * get_group_id(0) + l] = values[l * WG_SIZE];
}

// The clearance refresh of the nodes device_step listed as ~i (PDMESH_REFRESH_KERNEL, the GPU shape;
// the same rule and expressions as its inline refresh): entry k of the list (counters[COUNTER_CANDIDATES]
// entries) by work-group k, k + groups, ... (the launch covers n: as many groups as device_step's).
// The whole group searches the segments for one entry (kernels/clearance.cl, clearance_bound_group:
// bit for bit one work-item's search), so an entry costs a walk over n_segs / WG_SIZE segments per
// work-item instead of one work-item's walk over all of them. Accepted: the node's new budget, and
// its skin use (device_step's formula) into the maximum of step partials slot 6 of this group (only
// the maximum over all groups is used, and a maximum does not depend on the grouping); the entry stays
// ~i, which the host skips. Otherwise the entry becomes i, for the host's exact test (counters[COUNTER_HOST]).
__kernel __attribute__((reqd_work_group_size(WG_SIZE, 1, 1))) void refresh_budgets(
    const int n, __global int* counters, __global int* cand_index, __global const REAL* cand_rec, __global REAL* budget,
    __global const REAL* q_next, __global const REAL2* xy_build, __global const REAL* q_build,
    __global const uchar* skin_class, const REAL cutoff, const REAL skin_cutoff, __global const REAL* segs,
    const int n_segs, const REAL seg_scale, __global REAL* partials) {
  __local REAL lane_best[WG_SIZE];
  if (counters[WINDOW_HALT] != 0) return;  // uniform: the window was halted (kernels/window.cl)
  const int l = get_local_id(0), g = get_group_id(0);
  const int m = counters[COUNTER_CANDIDATES];
  if (g >= m) return;                               // uniform: no entry for this group
  REAL skin_use = (REAL)0;                          // work-item 0's
  for (int k = g; k < m; k += get_num_groups(0)) {  // uniform
    const int entry = cand_index[k];
    if (entry >= 0) continue;  // uniform: a candidate for the host
    const int i = ~entry;
    const REAL xi = cand_rec[4 * k], yi = cand_rec[4 * k + 1], dx = cand_rec[4 * k + 2], dy = cand_rec[4 * k + 3];
    const REAL xn = xi + dx, yn = yi + dy;
    const REAL ex = xn - xi, ey = yn - yi;
    // Its barriers order every work-item's read of cand_index[k] before work-item 0 rewrites it.
    const REAL d = clearance_bound_group(xn, yn, segs, n_segs, seg_scale, lane_best);
    if (l == 0) {
      const REAL fresh = clearance_accept(ex, ey, xn, yn, d);
      if (fresh > (REAL)0) {
        budget[i] = fresh;
        const REAL s =
            skin_use_of((REAL2)(xn, yn), q_next[i], xy_build[i], q_build[i], cutoff, skin_cutoff, skin_class[i]);
        skin_use = s > skin_use ? s : skin_use;
      } else {
        cand_index[k] = i;
        atomic_or(&counters[COUNTER_HOST], 1);
      }
    }
  }
  if (l == 0) {
    const REAL old = partials[STEP_PARTIALS * g + 6];
    partials[STEP_PARTIALS * g + 6] = skin_use > old ? skin_use : old;
  }
}

// Writes back the m positions the host decided (boundary nodes re-snapped, candidates moved or
// snapped): rec = (x, y, tx, ty, budget) per entry; recomputes q and the leaf there.
__kernel __attribute__((reqd_work_group_size(WG_SIZE, 1, 1))) void apply_host_moves(
    const int m, __global const int* rec_index, __global const REAL* rec, __global REAL2* xy, __global REAL* q,
    __global REAL* tx, __global REAL* ty, __global REAL* budget, __global int* node_leaf, BG_ARGS) {
  const int k = get_global_id(0);
  if (k >= m) return;
  const int i = rec_index[k];
  const REAL px = rec[5 * k], py = rec[5 * k + 1];
  xy[i] = (REAL2)(px, py);
  tx[i] = rec[5 * k + 2];
  ty[i] = rec[5 * k + 3];
  budget[i] = rec[5 * k + 4];
  REAL u, v;
  const int leaf = bg_locate(px, py, bg_origin_x, bg_origin_y, bg_inv_root, bg_grid, bg_root, bg_child, &u, &v);
  node_leaf[i] = leaf;
  q[i] = bg_interpolate(leaf, u, v, bg_corner, bg_q);
}
