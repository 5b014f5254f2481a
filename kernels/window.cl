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
void iteration_rule_body(const int groups, __global const REAL* partials, const int snap_entries,
                         __global REAL* snap_partials, __global int* step_counters, __global double* state,
                         __global double* ring, const int ring_rows, __global REAL* dt2_out) {
  if (atomic_or(&step_counters[WINDOW_HALT], 0) != 0) return;
  const int r = step_counters[WINDOW_ROWS];
  if (r >= ring_rows) {  // the host sizes the ring to the window: never, but never write past it
    atomic_xchg(&step_counters[WINDOW_HALT], 1);
    return;
  }
  // DeviceRun's sums, in group order: |F| and kinetic energy in double, the counts as integers,
  // the maxima by std::max's comparison.
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

__kernel void iteration_rule(const int groups, __global const REAL* partials, const int snap_entries,
                             __global REAL* snap_partials, __global int* step_counters, __global double* state,
                             __global double* ring, const int ring_rows, __global REAL* dt2_out) {
  if (get_global_id(0) != 0) return;
  iteration_rule_body(groups, partials, snap_entries, snap_partials, step_counters, state, ring, ring_rows, dt2_out);
}
#endif
