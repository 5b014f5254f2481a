// The end of one device-resident iteration on the device (host/opencl/device_window.*): one work-item
// (the last work-group of boundary_snap_rule, or the kernel iteration_rule where there are no boundary nodes)
// sums the per-group partials of device_step and boundary_snap in group order (as the host did), writes
// the iteration's history row into a ring the host reads once per window, runs the global time-step rule
// (GlobalTimeStep::update, host/sim/global_time_step.cpp, operation for operation in double) and hands
// the next device_step its dt^2. It halts the window (step_counters[WINDOW_HALT]; every later kernel of
// the window then does nothing) when the host must act: interior nodes for the exact test, a move or a
// sum that is not finite, or a skin use past the rebuild limit. Needs cl_khr_fp64 (the rule's state
// is double whatever REAL is); without it the host sums and runs the rule (DeviceWindow::device_rule).
#if defined(cl_khr_fp64)
#pragma OPENCL EXTENSION cl_khr_fp64 : enable
#pragma OPENCL FP_CONTRACT OFF

// RING_*, STATE_*, COUNTER_*, WINDOW_* slots, GM_RUN_LENGTH, GM_GROW, GM_SHRINK, STEP_PARTIALS and
// BOUNDARY_PARTIALS: defined by the program builder from host/opencl/device_window.hpp,
// step_program.hpp and GlobalTimeStep.
// The rule, run by one work-item: the kernel iteration_rule below (runs without boundary nodes) or the
// last work-group of boundary_snap_rule (kernels/boundary.cl), which saves a launch per iteration.
// In boundary_snap_rule other work-groups of the same launch wrote snap_partials and read the halt
// flag: those go through atomics (reduce.cl, atomic_load_real).

// RULE_AHEAD groups' partials in named values (an array might live in memory, each load then
// waiting before the next), then added in group order.
#define RULE_AHEAD 8
#define RULE_LOAD(j)                                                                                            \
  const REAL f##j = p[STEP_PARTIALS * j], e##j = p[STEP_PARTIALS * j + 1], m##j = p[STEP_PARTIALS * j + 2],     \
             w##j = p[STEP_PARTIALS * j + 3], c##j = p[STEP_PARTIALS * j + 4], x##j = p[STEP_PARTIALS * j + 5], \
             s##j = p[STEP_PARTIALS * j + 6]
#define RULE_ADD(j)                                                \
  force += (double)f##j;                                           \
  kinetic += (double)e##j;                                         \
  moving += (long)m##j;                                            \
  within += (long)w##j;                                            \
  coincident += (long)c##j;                                        \
  max_force = max_force < (double)x##j ? (double)x##j : max_force; \
  skin = skin < (double)s##j ? (double)s##j : skin
// The iteration's sums (DeviceRun's): |F| and kinetic energy in double, the counts as integers, the
// maxima by std::max's comparison.
typedef struct {
  double force, kinetic, max_force, skin, snap_skin;
  long moving, within, coincident, clamped, bad;
} RuleSums;

// The ring row this iteration writes, or -1 when the window is halted or its ring full (the host sizes
// the ring to the window: never, but never write past it).
int rule_open(__global int* step_counters, const int ring_rows) {
  if (atomic_or(&step_counters[WINDOW_HALT], 0) != 0) return -1;
  const int r = step_counters[WINDOW_ROWS];
  if (r >= ring_rows) {
    atomic_xchg(&step_counters[WINDOW_HALT], 1);
    return -1;
  }
  return r;
}

// The sums by one work-item, in group order.
void rule_sums_serial(const int groups, __global const REAL* partials, const int snap_entries,
                      __global REAL* snap_partials, RuleSums* sums) {
  // The partials of RULE_AHEAD groups are loaded before any of them is added: a GPU issues one
  // work-item's instructions in order, so a loop that adds each group's partials right after loading
  // them waits a memory latency per group (at millions of nodes longer than the step itself). The
  // same additions and comparisons in the same order, so the same bits.
  double force = 0.0, kinetic = 0.0, max_force = 0.0, skin = 0.0;
  long moving = 0, within = 0, coincident = 0;
  int g = 0;
  for (; g + RULE_AHEAD <= groups; g += RULE_AHEAD) {
    __global const REAL* p = partials + STEP_PARTIALS * g;
    RULE_LOAD(0);
    RULE_LOAD(1);
    RULE_LOAD(2);
    RULE_LOAD(3);
    RULE_LOAD(4);
    RULE_LOAD(5);
    RULE_LOAD(6);
    RULE_LOAD(7);
    RULE_ADD(0);
    RULE_ADD(1);
    RULE_ADD(2);
    RULE_ADD(3);
    RULE_ADD(4);
    RULE_ADD(5);
    RULE_ADD(6);
    RULE_ADD(7);
  }
  for (; g < groups; ++g) {
    __global const REAL* p = partials + STEP_PARTIALS * g;
    force += (double)p[0];
    kinetic += (double)p[1];
    moving += (long)p[2];
    within += (long)p[3];
    coincident += (long)p[4];
    max_force = max_force < (double)p[5] ? (double)p[5] : max_force;
    skin = skin < (double)p[6] ? (double)p[6] : skin;
  }
  long clamped = 0, bad = 0;
  double snap_skin = 0.0;
  for (int g = 0; g + BOUNDARY_PARTIALS <= snap_entries; g += BOUNDARY_PARTIALS) {
    clamped += (long)atomic_load_real(snap_partials + g);
    bad += (long)atomic_load_real(snap_partials + g + 1);
    const double skin_g = (double)atomic_load_real(snap_partials + g + 2);
    snap_skin = snap_skin < skin_g ? skin_g : snap_skin;
  }
  sums->force = force;
  sums->kinetic = kinetic;
  sums->max_force = max_force;
  sums->skin = skin;
  sums->snap_skin = snap_skin;
  sums->moving = moving;
  sums->within = within;
  sums->coincident = coincident;
  sums->clamped = clamped;
  sums->bad = bad;
}

// Row r of the ring from the sums, the time-step rule, the skin use, and the halt test.
void rule_close(const int r, const RuleSums* sums, __global int* step_counters, __global double* state,
                __global double* ring, __global REAL* dt2_out) {
  const double force = sums->force, kinetic = sums->kinetic, max_force = sums->max_force, skin = sums->skin,
               snap_skin = sums->snap_skin;
  const long moving = sums->moving, within = sums->within, coincident = sums->coincident, clamped = sums->clamped,
             bad = sums->bad;
  __global double* row = ring + RING_SIZE * r;
  row[RING_FORCE] = force;
  row[RING_KINETIC] = kinetic;
  row[RING_MOVING] = (double)moving;
  row[RING_WITHIN] = (double)within;
  row[RING_COINCIDENT] = (double)coincident;
  row[RING_MAX_FORCE] = max_force;
  row[RING_SKIN] = skin;
  row[RING_CLAMPED] = (double)clamped;
  row[RING_SNAP_BAD] = (double)bad;
  row[RING_SNAP_SKIN] = snap_skin;
  row[RING_DT] = state[STATE_DT];
  // The list holds the host's candidates and (PDMESH_REFRESH_KERNEL) refreshed nodes, which the host
  // skips: it is read only when it holds a candidate, and otherwise emptied for the next iteration.
  const int host = step_counters[COUNTER_HOST] != 0;
  row[RING_CANDIDATES] = host ? (double)step_counters[COUNTER_CANDIDATES] : 0.0;
  if (!host) step_counters[COUNTER_CANDIDATES] = 0;
  row[RING_NON_FINITE] = (double)step_counters[COUNTER_NON_FINITE];
  // GlobalTimeStep::update(max_force).
  double dt = state[STATE_DT];
  if (state[STATE_HAS_PREVIOUS] != 0.0) {
    const double before = state[STATE_PREVIOUS];
    int decreases = (int)state[STATE_DECREASES], increases = (int)state[STATE_INCREASES];
    if (max_force < before) {
      if (++decreases == GM_RUN_LENGTH) {
        dt *= GM_GROW;
        decreases = 0;
        increases = 0;
      }
    } else {
      decreases = 0;
      if (max_force > before && ++increases == GM_RUN_LENGTH) {
        dt *= GM_SHRINK;
        increases = 0;
      }
    }
    state[STATE_DECREASES] = (double)decreases;
    state[STATE_INCREASES] = (double)increases;
  }
  state[STATE_PREVIOUS] = max_force;
  state[STATE_HAS_PREVIOUS] = 1.0;
  state[STATE_DT] = dt;
  dt2_out[0] = (REAL)(dt * dt);
  // The skin use since the last build (the host's skin_use_), as DeviceRun keeps it.
  double used = state[STATE_SKIN];
  used = used < skin ? skin : used;
  used = used < snap_skin ? snap_skin : used;
  state[STATE_SKIN] = used;
  step_counters[WINDOW_ROWS] = r + 1;
  if (host || step_counters[COUNTER_NON_FINITE] != 0 || bad != 0 || !isfinite(force) || !isfinite(kinetic) ||
      used > state[STATE_SKIN_LIMIT])
    atomic_xchg(&step_counters[WINDOW_HALT], 1);
}

void iteration_rule_body(const int groups, __global const REAL* partials, const int snap_entries,
                         __global REAL* snap_partials, __global int* step_counters, __global double* state,
                         __global double* ring, const int ring_rows, __global REAL* dt2_out) {
  const int r = rule_open(step_counters, ring_rows);
  if (r < 0) return;
  RuleSums sums;
  rule_sums_serial(groups, partials, snap_entries, snap_partials, &sums);
  rule_close(r, &sums, step_counters, state, ring, dt2_out);
}

#if PDMESH_RULE_GROUP
// Local memory of the group-wide rule, declared by its kernels.
#define RULE_LOCALS                          \
  __local double rule_stage[2 * RULE_CHUNK]; \
  __local long rule_counts[5 * WG_SIZE];     \
  __local double rule_maxima[3 * WG_SIZE];   \
  __local int rule_row
#define RULE_LOCALS_PASS rule_stage, rule_counts, rule_maxima, &rule_row
#define RULE_MAX(a, b) ((a) < (b) ? (b) : (a))
// The sums by a whole work-group (the GPU shape, PDMESH_RULE_GROUP): one work-item adding every group's
// partials waits for its loads and converts and compares 7 values per group in one dependent stream
// (at millions of nodes ten times the step itself). Here the work-items load RULE_CHUNK groups at a
// time (RULE_CHUNK / WG_SIZE each, adjacent work-items adjacent groups), keep the counts and maxima
// of the groups they loaded, and stage |F| and kinetic energy in local memory; work-item 0 adds those
// two in group order, two independent additions per group. The counts are integers and the maxima
// are of +0.0 and whatever the comparison lets past it (never -0.0 or NaN), so the per-work-item
// results combined give the same values in any order; the two double sums are the same additions in
// the same order as rule_sums_serial's: the same bits.
// Called by every work-item of the group (it has barriers). Data live across its barriers stays a
// few scalars per work-item: PoCL 3.1 keeps such data per work-item on its worker thread's stack.
void rule_sums_group(const int groups, __global const REAL* partials, const int snap_entries,
                     __global REAL* snap_partials, RuleSums* sums, __local double* stage, __local long* counts,
                     __local double* maxima) {
  const int l = get_local_id(0);
  double force = 0.0, kinetic = 0.0, max_force = 0.0, skin = 0.0;
  long moving = 0, within = 0, coincident = 0;
  for (int base = 0; base < groups; base += RULE_CHUNK) {
#pragma unroll
    for (int k = 0; k < (RULE_CHUNK + WG_SIZE - 1) / WG_SIZE; ++k) {  // the chunk's loads issued before their use
      const int j = k * WG_SIZE + l, g = base + j;
      if (j < RULE_CHUNK && g < groups) {
        __global const REAL* p = partials + STEP_PARTIALS * g;
        stage[j] = (double)p[0];
        stage[RULE_CHUNK + j] = (double)p[1];
        moving += (long)p[2];
        within += (long)p[3];
        coincident += (long)p[4];
        max_force = RULE_MAX(max_force, (double)p[5]);
        skin = RULE_MAX(skin, (double)p[6]);
      }
    }
    barrier(CLK_LOCAL_MEM_FENCE);
    if (l == 0) {
      const int n = groups - base < RULE_CHUNK ? groups - base : RULE_CHUNK;
#pragma unroll 8
      for (int j = 0; j < n; ++j) {  // unrolled: the local loads run ahead of the two chains of additions
        force += stage[j];
        kinetic += stage[RULE_CHUNK + j];
      }
    }
    barrier(CLK_LOCAL_MEM_FENCE);  // the stage is refilled next
  }
  long clamped = 0, bad = 0;
  double snap_skin = 0.0;
  for (int g = BOUNDARY_PARTIALS * l; g + BOUNDARY_PARTIALS <= snap_entries; g += BOUNDARY_PARTIALS * WG_SIZE) {
    clamped += (long)atomic_load_real(snap_partials + g);
    bad += (long)atomic_load_real(snap_partials + g + 1);
    snap_skin = RULE_MAX(snap_skin, (double)atomic_load_real(snap_partials + g + 2));
  }
  counts[l] = moving;
  counts[WG_SIZE + l] = within;
  counts[2 * WG_SIZE + l] = coincident;
  counts[3 * WG_SIZE + l] = clamped;
  counts[4 * WG_SIZE + l] = bad;
  maxima[l] = max_force;
  maxima[WG_SIZE + l] = skin;
  maxima[2 * WG_SIZE + l] = snap_skin;
  barrier(CLK_LOCAL_MEM_FENCE);
  if (l == 0) {
    sums->force = force;
    sums->kinetic = kinetic;
    sums->moving = sums->within = sums->coincident = sums->clamped = sums->bad = 0;
    sums->max_force = sums->skin = sums->snap_skin = 0.0;
    for (int k = 0; k < WG_SIZE; ++k) {
      sums->moving += counts[k];
      sums->within += counts[WG_SIZE + k];
      sums->coincident += counts[2 * WG_SIZE + k];
      sums->clamped += counts[3 * WG_SIZE + k];
      sums->bad += counts[4 * WG_SIZE + k];
      sums->max_force = RULE_MAX(sums->max_force, maxima[k]);
      sums->skin = RULE_MAX(sums->skin, maxima[WG_SIZE + k]);
      sums->snap_skin = RULE_MAX(sums->snap_skin, maxima[2 * WG_SIZE + k]);
    }
  }
}

// iteration_rule_body by the whole group (every work-item calls it): work-item 0 opens the row and
// tells the others through local memory (row); the sums; work-item 0 closes the row.
void iteration_rule_group(const int groups, __global const REAL* partials, const int snap_entries,
                          __global REAL* snap_partials, __global int* step_counters, __global double* state,
                          __global double* ring, const int ring_rows, __global REAL* dt2_out, __local double* stage,
                          __local long* counts, __local double* maxima, __local int* row) {
  if (get_local_id(0) == 0) *row = rule_open(step_counters, ring_rows);
  barrier(CLK_LOCAL_MEM_FENCE);
  const int r = *row;
  if (r >= 0) {  // the same for the whole group
    RuleSums sums;
    rule_sums_group(groups, partials, snap_entries, snap_partials, &sums, stage, counts, maxima);
    if (get_local_id(0) == 0) rule_close(r, &sums, step_counters, state, ring, dt2_out);
  }
}

// Launched as one work-group.
__kernel __attribute__((reqd_work_group_size(WG_SIZE, 1, 1))) void iteration_rule(
    const int groups, __global const REAL* partials, const int snap_entries, __global REAL* snap_partials,
    __global int* step_counters, __global double* state, __global double* ring, const int ring_rows,
    __global REAL* dt2_out) {
  RULE_LOCALS;
  iteration_rule_group(groups, partials, snap_entries, snap_partials, step_counters, state, ring, ring_rows, dt2_out,
                       RULE_LOCALS_PASS);
}
#else
// Launched as one work-item.
__kernel void iteration_rule(const int groups, __global const REAL* partials, const int snap_entries,
                             __global REAL* snap_partials, __global int* step_counters, __global double* state,
                             __global double* ring, const int ring_rows, __global REAL* dt2_out) {
  if (get_global_id(0) != 0) return;
  iteration_rule_body(groups, partials, snap_entries, snap_partials, step_counters, state, ring, ring_rows, dt2_out);
}
#endif
#endif
