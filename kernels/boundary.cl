// Boundary handling on the device (host/opencl/device_boundary.*): every boundary node is re-snapped
// to the closest point of its own curve within its allowed arc range, the host's
// BoundaryHandler::move_boundary_nodes + closest_on_curve_range (host/sim/boundary_handling.cpp)
// operation for operation, so that a double run is bit-identical to the host reference. The Jacobi
// rule reads the old arc positions (arcs_in) and writes the new ones (arcs_out): the host swaps them.
#pragma OPENCL FP_CONTRACT OFF

// BOUNDARY_PARTIALS (clamped count, non-finite targets | max skin use): defined by the program builder.
// MAX_GAP_FRACTION: BoundaryHandler::kMaxGapFraction, defined by the program builder.
#ifndef MAX_GAP_FRACTION
#error "MAX_GAP_FRACTION must be defined by the program builder"
#endif

// unit(v) of boundary_handling.cpp: v / |v| as (1 / |v|) v, zero for a zero vector.
REAL2 unit2(const REAL2 v) {
  const REAL n = sqrt(v.x * v.x + v.y * v.y);
  if (n > (REAL)0) {
    const REAL s = (REAL)1 / n;
    return (REAL2)(s * v.x, s * v.y);
  }
  return (REAL2)((REAL)0, (REAL)0);
}

// Unit tangent of segment k (points p[k] -> p[k + 1]; p: x, y interleaved).
REAL2 segment_tangent(__global const REAL* p, const int k) {
  return unit2((REAL2)(p[2 * k + 2] - p[2 * k], p[2 * k + 3] - p[2 * k + 1]));
}

// closest_on_curve_range on one curve: points p (segments + 1 of them, interleaved), cumulative arc
// lengths arc. std::max, std::min and std::clamp written as libstdc++ evaluates them (the same
// comparison, the same operand returned), so NaN and signed zeros come out the same too.
void closest_on_curve(__global const REAL* p, __global const REAL* arc, const int segments, const REAL px,
                      const REAL py, const REAL arc_lo, const REAL arc_hi, REAL2* best_p, REAL* best_arc,
                      REAL2* best_tangent) {
  REAL best2 = INFINITY;
  *best_p = (REAL2)((REAL)0, (REAL)0);
  *best_arc = (REAL)0;
  *best_tangent = (REAL2)((REAL)0, (REAL)0);
  // std::upper_bound(arc, arc + segments + 1, arc_lo) - 1: the first segment that reaches arc_lo.
  int first = 0, count = segments + 1;
  while (count > 0) {
    const int step = count / 2;
    if (!(arc_lo < arc[first + step])) {
      first += step + 1;
      count -= step + 1;
    } else {
      count = step;
    }
  }
  int k = first - 1;
  k = k < 0 ? 0 : (segments - 1 < k ? segments - 1 : k);
  for (; k < segments && arc[k] <= arc_hi; ++k) {
    const REAL s0 = arc[k], len = arc[k + 1] - s0;
    const REAL lo_t = (arc_lo - s0) / len, hi_t = (arc_hi - s0) / len;
    const REAL t_lo = (REAL)0 < lo_t ? lo_t : (REAL)0;
    const REAL t_hi = hi_t < (REAL)1 ? hi_t : (REAL)1;
    if (t_lo > t_hi) continue;
    const REAL ax = p[2 * k], ay = p[2 * k + 1], bx = p[2 * k + 2], by = p[2 * k + 3];
    const REAL dx = bx - ax, dy = by - ay;
    const REAL v = ((px - ax) * dx + (py - ay) * dy) / (dx * dx + dy * dy);
    const REAL t = v < t_lo ? t_lo : (t_hi < v ? t_hi : v);
    REAL2 on;
    const REAL dist2 = segment_point(ax, ay, bx, by, dx, dy, t, px, py, &on);  // clearance.cl
    if (dist2 < best2) {
      best2 = dist2;
      *best_p = on;
      *best_arc = t == (REAL)1 ? arc[k + 1] : s0 + t * len;
      // At a vertex the node slides along the mean direction of both segments.
      REAL2 tangent = segment_tangent(p, k);
      if (t == (REAL)0 && k > 0) {
        const REAL2 other = segment_tangent(p, k - 1);
        tangent = unit2((REAL2)(tangent.x + other.x, tangent.y + other.y));
      }
      if (t == (REAL)1 && k + 1 < segments) {
        const REAL2 other = segment_tangent(p, k + 1);
        tangent = unit2((REAL2)(tangent.x + other.x, tangent.y + other.y));
      }
      *best_tangent = tangent;
    }
  }
}

// One work-item per boundary slot s (node slot_node[s], in node index order as device_step's bslot):
// its move (x, y, dx, dy) = brec[4 s ..] from device_step; its curve slot_curve[s]; its entry
// slot_pos[s] in the arc positions of all curve lists laid end to end (curve_pt: each curve's first
// point in pts/arc, curves + 1 entries). Writes the node's position, tangent, arc position, spacing and
// leaf (as apply_host_moves did with the host's result), its new (x, y, tx, ty) over its brec record
// (what sync_boundary reads back), and per group: clamped moves, non-finite
// targets (nothing is written for those: the host reports them), and the largest skin use (the
// formula of device_step). step_counters[COUNTER_NON_FINITE] != 0 (device_step's flag for a move that is not finite):
// nothing is written but the partials. boundary_snap's arguments, shared by its two kernels.
#define SNAP_ARGS                                                                                                      \
  const int m, __global const int *slot_node, __global const int *slot_curve, __global const int *slot_pos,            \
      __global const int *curve_pt, __global const REAL *pts, __global const REAL *pt_arc,                             \
      __global const REAL *arcs_in, __global REAL *arcs_out, __global REAL *brec, __global REAL2 *xy,                  \
      __global REAL *q, __global REAL *tx, __global REAL *ty, __global int *node_leaf, __global const REAL2 *xy_build, \
      __global const REAL *q_build, __global const uchar *skin_class, const REAL cutoff, const REAL skin_cutoff,       \
      __global int *step_counters, __global REAL *partials, BG_ARGS
#define SNAP_PASS                                                                                               \
  m, slot_node, slot_curve, slot_pos, curve_pt, pts, pt_arc, arcs_in, arcs_out, brec, xy, q, tx, ty, node_leaf, \
      xy_build, q_build, skin_class, cutoff, skin_cutoff, step_counters, partials, BG_PASS

// snap_prefetch: on a CPU (the vector shape on x86), the spacing lookup of the slots ahead prefetched,
// as device_step's step_prefetch does for its nodes: the leaf's cell and corner indices of slot
// s + SNAP_PREFETCH_AHEAD, and the corner spacings of slot s + SNAP_PREFETCH_AHEAD / 2, whose corner
// indices the same call made SNAP_PREFETCH_AHEAD / 2 slots before. A group's work-items run one after
// the other on one core, and these loads otherwise miss (the background field is larger than the
// caches near the cores). The leaf is the node's before the snap, which a snap rarely leaves. A
// prefetch changes no value; elsewhere it does nothing.
#define SNAP_PREFETCH_AHEAD 4
void snap_prefetch(const int s, const int m, __global const int* slot_node, __global const int* node_leaf,
                   __global const int* bg_cell, __global const int* bg_corner, __global const REAL* bg_q) {
#if PDMESH_FORCE_LOOP_VECTOR && defined(__x86_64__)
  if (s + SNAP_PREFETCH_AHEAD < m)
    prefetch_leaf_lookup(node_leaf[slot_node[s + SNAP_PREFETCH_AHEAD]], bg_cell, bg_corner);
  if (s + SNAP_PREFETCH_AHEAD / 2 < m)
    prefetch_leaf_spacings(node_leaf[slot_node[s + SNAP_PREFETCH_AHEAD / 2]], bg_corner, bg_q);
#endif
}

// Inlined into both kernels: a call with this many arguments costs GPU registers and scratch.
__attribute__((always_inline)) void boundary_snap_body(__local REAL* values, __local int* halt, SNAP_ARGS) {
  const int s = get_global_id(0), l = get_local_id(0);
  REAL clamped = (REAL)0, bad = (REAL)0, skin_use = (REAL)0;
  // device_step found a move that is not finite: nothing is written (tangents are updated in place).
  // The window was halted before this iteration (kernels/window.cl): nothing at all.
  // (boundary_snap_rule's last group may set the flag while this launch runs: an atomic read, by one
  // work-item, before any group counted itself done.)
  if (get_local_id(0) == 0) *halt = atomic_or(&step_counters[WINDOW_HALT], 0);
  barrier(CLK_LOCAL_MEM_FENCE);
  if (*halt != 0) return;
  const int halted = step_counters[COUNTER_NON_FINITE] != 0;
  if (s < m) {
    snap_prefetch(s, m, slot_node, node_leaf, bg_cell, bg_corner, bg_q);
    const int i = slot_node[s], c = slot_curve[s], pos = slot_pos[s];
    const REAL old = arcs_in[pos];
    const REAL lo = old - MAX_GAP_FRACTION * (old - arcs_in[pos - 1]);
    const REAL hi = old + MAX_GAP_FRACTION * (arcs_in[pos + 1] - old);
    const REAL px = brec[4 * s] + brec[4 * s + 2], py = brec[4 * s + 1] + brec[4 * s + 3];
    if (!isfinite(px) || !isfinite(py)) {
      bad = (REAL)1;
    } else if (!halted) {
      const int first = curve_pt[c];
      REAL2 on, tangent;
      REAL arc;
      closest_on_curve(pts + 2 * first, pt_arc + first, curve_pt[c + 1] - first - 1, px, py, lo, hi, &on, &arc,
                       &tangent);
      if (arc == lo || arc == hi) clamped = (REAL)1;
      arcs_out[pos] = arc;
      brec[4 * s] = on.x;  // the slot's record becomes its new state (read back by sync_boundary)
      brec[4 * s + 1] = on.y;
      brec[4 * s + 2] = tangent.x;
      brec[4 * s + 3] = tangent.y;
      xy[i] = on;
      tx[i] = tangent.x;
      ty[i] = tangent.y;
      // The node's leaf from the last step seeds the lookup, as in device_step (bg_locate_cached: the
      // same leaf and (u, v) bit for bit as a descent from the root; a snap moves a node by a fraction
      // of a cell, so the guess nearly always holds and the 15-20 dependent loads of a descent are skipped).
      int leaf = node_leaf[i];
      const REAL qn = bg_spacing_cached(on.x, on.y, &leaf, BG_PASS);
      node_leaf[i] = leaf;
      q[i] = qn;
      skin_use = skin_use_of(on, qn, xy_build[i], q_build[i], cutoff, skin_cutoff, skin_class[i]);
    }
  }
  values[l] = clamped;
  values[WG_SIZE + l] = bad;
  values[2 * WG_SIZE + l] = skin_use;
  group_reduce(values, BOUNDARY_PARTIALS, 2);
  if (l < BOUNDARY_PARTIALS) atomic_store_real(partials + BOUNDARY_PARTIALS * get_group_id(0) + l, values[l * WG_SIZE]);
}

__kernel __attribute__((reqd_work_group_size(WG_SIZE, 1, 1))) void boundary_snap(SNAP_ARGS) {
  __local REAL values[BOUNDARY_PARTIALS * WG_SIZE];
  __local int halt;
  boundary_snap_body(values, &halt, SNAP_PASS);
}

#if defined(cl_khr_fp64)
// boundary_snap, then the iteration's end (kernels/window.cl, iteration_rule_body) in its last
// work-group, one launch instead of two: each group's work-item 0 counts the group as done
// (step_counters[COUNTER_SNAP_DONE], an integer atomic) after the group's partials are written and
// fenced; the group that counts last sums every group's partials (atomic reads, reduce.cl) and runs the rule,
// and sets the count back to 0 for the next iteration. Arguments after boundary_snap's: iteration_rule's.
__kernel __attribute__((reqd_work_group_size(WG_SIZE, 1, 1))) void boundary_snap_rule(
    SNAP_ARGS, const int groups, __global const REAL* step_partials, __global double* state, __global double* ring,
    const int ring_rows, __global REAL* dt2_out) {
  __local REAL values[BOUNDARY_PARTIALS * WG_SIZE];
  __local int halt;
  boundary_snap_body(values, &halt, SNAP_PASS);  // halted before this iteration: nothing (the rule neither)
  barrier(CLK_GLOBAL_MEM_FENCE);                 // this group's partials (work-items l < BOUNDARY_PARTIALS) are written
#if PDMESH_RULE_GROUP
  // The whole last group runs the rule (window.cl, iteration_rule_group): work-item 0's count decides
  // for the group, through local memory.
  RULE_LOCALS;
  __local int last;
  if (get_local_id(0) == 0) {
    mem_fence(CLK_GLOBAL_MEM_FENCE);
    last = atomic_inc(&step_counters[COUNTER_SNAP_DONE]) == (int)get_num_groups(0) - 1;
    if (last) {
      mem_fence(CLK_GLOBAL_MEM_FENCE);  // every other group's partials were written before its count
      atomic_xchg(&step_counters[COUNTER_SNAP_DONE], 0);
    }
  }
  barrier(CLK_LOCAL_MEM_FENCE | CLK_GLOBAL_MEM_FENCE);
  if (last)  // the same for the whole group
    iteration_rule_group(groups, step_partials, BOUNDARY_PARTIALS * (int)get_num_groups(0), partials, step_counters,
                         state, ring, ring_rows, dt2_out, RULE_LOCALS_PASS);
#else
  if (get_local_id(0) == 0) {
    mem_fence(CLK_GLOBAL_MEM_FENCE);
    if (atomic_inc(&step_counters[COUNTER_SNAP_DONE]) == (int)get_num_groups(0) - 1) {
      mem_fence(CLK_GLOBAL_MEM_FENCE);  // every other group's partials were written before its count
      atomic_xchg(&step_counters[COUNTER_SNAP_DONE], 0);
      iteration_rule_body(groups, step_partials, BOUNDARY_PARTIALS * (int)get_num_groups(0), partials, step_counters,
                          state, ring, ring_rows, dt2_out);
    }
  }
#endif
}
#endif
