// Windows of device-resident iterations enqueued without a host wait (docs/opencl.md, "One
// iteration"): after each iteration's device_step and boundary_snap, the single-work-item kernel
// iteration_rule (kernels/window.cl) sums the per-group partials, writes the iteration's history row
// into a ring, runs the global time-step rule on a copy of its state and hands the next step its dt^2;
// it halts the window when the host must act (nodes for the exact test, a non-finite move or sum, the
// skin used up). The host writes the rule's state and the counters once per window and reads the ring
// and the counters once at its end (one wait); it then replays the rows one by one through the host
// driver's loop (sim/iteration_loop.hpp: history, progress, callbacks, GlobalTimeStep, which it checks
// against the device's dt).
// Without cl_khr_fp64 (the rule's state is double) the host sums the partials itself, one iteration per
// window (tests force that path with the environment variable
// PDMESH_TEST_HOST_TIME_STEP_RULE).
#pragma once
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "opencl/buffer.hpp"
#include "opencl/context.hpp"
#include "opencl/step_program.hpp"
#include "sim/global_time_step.hpp"

namespace pdmesh::ocl {

// One history row of the ring (doubles), as iteration_rule writes it.
enum WindowRowSlot : int {
  kRingForce = 0,        // sum of |F| over moving nodes
  kRingKinetic = 1,      // sum of the kinetic terms
  kRingMoving = 2,       // moving nodes
  kRingWithin = 3,       // pairs within the cut-off
  kRingCoincident = 4,   // coincident pairs
  kRingMaxForce = 5,     // the largest |F|
  kRingSkin = 6,         // the largest skin use of device_step's interior nodes
  kRingClamped = 7,      // boundary_snap: clamped moves
  kRingSnapBad = 8,      // boundary_snap: non-finite targets
  kRingSnapSkin = 9,     // boundary_snap: the largest skin use
  kRingDt = 10,          // the global time step this iteration used
  kRingCandidates = 11,  // interior nodes for the host's exact test
  kRingNonFinite = 12,   // device_step's flag for a move that is not finite
  kRingSize = 13
};
// The rule's state on the device (doubles): GlobalTimeStep::State and the skin use since the last build.
enum WindowStateSlot : int {
  kStateDt = 0,
  kStatePrevious = 1,
  kStateHasPrevious = 2,
  kStateDecreases = 3,
  kStateIncreases = 4,
  kStateSkin = 5,
  kStateSkinLimit = 6,
  kStateSize = 7
};
// The step counters (ints; device_step's candidate count and non-finite flag come first;
// kCounterSnapDone: boundary_snap_rule's count of finished work-groups, back to 0 after each launch;
// kCounterHost: set when an entry of the candidate list is for the host (the list also holds the nodes
// whose clearance refresh succeeded in refresh_budgets, as ~i, which the host skips).
enum WindowCounter : int {
  kCounterCandidates = 0,
  kCounterNonFinite = 1,
  kWindowHalt = 2,
  kWindowRows = 3,
  kCounterSnapDone = 4,
  kCounterHost = 5,
  kWindowCounters = 6
};

// Iterations one window enqueues at most (the ring's rows): the host reads the history this often.
inline constexpr int kWindowLength = 32;

// The slots and the rule's constants as defines for the program builder (step_program_defines).
std::map<std::string, std::string> window_defines();

template <typename Real>
class DeviceWindow {
 public:
  // device_rule: iteration_rule runs (the device has cl_khr_fp64); else the host sums the partials.
  DeviceWindow(Context& ctx, bool device_rule);
  bool device_rule() const { return device_rule_; }
  // Iterations the next window may enqueue (kWindowLength, or 1 with the host's sums).
  int max_length() const { return device_rule_ ? kWindowLength : 1; }
  // dt^2 of the next device_step (device_step reads it).
  Buffer<Real>& dt2() { return dt2_; }

  // Before a window: zero counters, the rule's state and dt^2 of its first step (3 writes, not waited on).
  void begin(const GlobalTimeStep& gm, double skin_use, double skin_limit, Buffer<std::int32_t>& counters);
  // After each iteration's device_step where no boundary_snap runs: iteration_rule (device rule only).
  // Where one runs, boundary_snap_rule runs the rule in its last work-group: rule_args appends the
  // rule's arguments after boundary_snap's.
  void rule_args(ArgSetter& a, std::size_t groups, Buffer<Real>& partials);
  void enqueue_rule(StepProgram& program, std::size_t groups, Buffer<Real>& partials, std::size_t snap_entries,
                    Buffer<Real>& snap_partials, Buffer<std::int32_t>& counters);
  // After the window's iterations, in two halves so that the host can work while the device runs
  // them: enqueue_reads enqueues the reads of the ring and the counters (with the host's sums, the
  // partials) and flushes the queue, no wait; complete waits (one wait) and returns how many
  // iterations ran. Their rows are row(0 ..).
  void enqueue_reads(Context& ctx, std::size_t groups, Buffer<Real>& partials, std::size_t snap_entries,
                     Buffer<Real>& snap_partials, Buffer<std::int32_t>& counters);
  int complete(Context& ctx, std::size_t groups, std::size_t snap_entries);
  const double* row(int k) const {
    return rows_.data() + static_cast<std::size_t>(kRingSize) * static_cast<std::size_t>(k);
  }
  // Transfers enqueued by the last begin() + enqueue_reads(), and their bytes (DeviceRunStats).
  std::uint64_t transfers = 0, bytes_up = 0, bytes_down = 0;

 private:
  Context& ctx_;
  bool device_rule_;
  Buffer<double> state_, ring_;
  Buffer<Real> dt2_;
  std::vector<double> rows_, state_host_;
  std::vector<Real> dt2_host_, part_host_, snap_host_;
  std::vector<std::int32_t> counters_host_;
  const std::vector<std::int32_t> zero_counters_ = std::vector<std::int32_t>(kWindowCounters, 0);
};

}  // namespace pdmesh::ocl
