// The device-resident simulation: positions, q, kinds, neighbour lists and the boundary state (arc
// positions, tangents; boundary nodes are re-snapped on the device) stay on the OpenCL device across
// iterations; per iteration the host downloads only the interior nodes whose clearance budget ran out
// (the exact inside test) and per-work-group partial sums. See docs/opencl.md.
#pragma once
#include <cstdint>

#include <memory>

#include "opencl/command_counts.hpp"
#include "opencl/context.hpp"
#include "sim/simulation.hpp"

namespace pdmesh::ocl {

// Where the time and the bytes went (pdmesh bench: docs/performance.md). Seconds are wall times.
struct DeviceRunStats {
  int iterations = 0;
  int rebuilds = 0;        // neighbour-list builds (Verlet skin)
  int windows = 0;         // windows of iterations enqueued without a wait (device_window.hpp)
  int ahead_windows = 0;   // of them, begun while the host measured a convergence check's mesh
  int saved_restores = 0;  // saved positions read back from the device's build state after such a check
  // With the measurement overlapped (DeviceRun::overlap_): iterations the device ran while the host measured,
  // beyond the window it ends on (their rows held back until the rule went on, or dropped at a stop), and
  // the neighbour-list builds among them.
  int ahead_rows = 0;
  int ahead_rebuilds = 0;
  CommandCounts rebuild_commands;      // the commands of the rebuilds (and the state they save), all of them
  int snap_rebuilds = 0;               // of those, forced by a snap alone (the skin had room left)
  double largest_spacing_ratio = 0.0;  // of any build (DeviceNeighbours::spacing_ratio; skin classes: device_run.hpp)
  int gathers = 0;  // neighbour build passes: one per rebuild, more when grids or rows outgrew their capacities
  std::uint64_t outgrown_rows = 0;  // rows that outgrew their capacities, summed over the passes
  std::size_t sampled_builds = 0;   // builds laid out from a sampled estimate (no counts yet: device_neighbours.hpp)
  int stride = 0;                   // the longest neighbour row of any build (rows are compact)
  std::uint64_t launches = 0;       // kernel launches
  std::uint64_t transfers = 0;      // reads + writes enqueued
  std::uint64_t bytes_down = 0, bytes_up = 0;  // all iterations, including rebuilds, excluding setup
  std::uint64_t setup_bytes = 0;               // the initial upload (nodes, background field), not in bytes_up
  std::uint64_t pairs_listed = 0;              // list entries within the skin radius, summed over builds
  std::uint64_t rebuild_candidates = 0;        // candidate pairs whose distance the rebuilds computed
  std::uint64_t candidates = 0;                // interior nodes handed to the host's exact test, all iterations
  double bin_seconds = 0.0;                    // host binning at rebuilds (0: the device bins, within gather_seconds)
  double gather_seconds = 0.0;                 // device neighbour build at rebuilds: binning, rows (one wait)
  double step_seconds = 0.0;                   // device_step and boundary_snap (+ the previous apply_host_moves,
                                               // and the partials: one wait)
  double download_seconds = 0.0;               // candidate records
  double host_seconds = 0.0;                   // the flagged interior nodes' exact test on the host
  double upload_seconds = 0.0;                 // enqueueing host positions back + apply_host_moves (not waited on)
  double population_seconds = 0.0;             // population events: state read back, the host event, re-upload
  double population_transfer_seconds = 0.0;    // of which the read-back and the re-upload
  std::size_t device_bytes = 0;                // device buffers at the end
};

// The neighbour rows' entries per node assumed before the first build (the rows are compact: a build
// sizes them to the entries it finds, docs/opencl.md "Neighbour lists: Verlet skin").
inline constexpr int kInitialStride = 16;

// Device memory a run needs with compact neighbour rows of `entries_per_node` entries per node on
// average (a lower bound; docs/opencl.md): in total, and for its largest buffer (the neighbour rows).
struct DeviceMemoryNeed {
  std::uint64_t total = 0, largest = 0;
};
// momentum: SimOptions::momentum > 0 (2 more reals per node, the carried moves).
DeviceMemoryNeed device_memory_need(std::size_t nodes, std::size_t boundary_nodes, std::uint64_t field_bytes,
                                    std::size_t real_bytes, int entries_per_node = kInitialStride,
                                    bool momentum = false);

// Throws LimitError (exit 2) naming the bytes needed, the device's global memory and largest
// allocation, and what to do instead (--precision float, --device host, a coarser spacing), when
// device_memory_need exceeds either, or when there are more nodes than the device's 32-bit node
// indices allow. Run before the first allocation of a device run (kInitialStride entries per node) and
// before the neighbour rows grow (their new size per node, rounded up).
void check_device_memory(const DeviceInfo& device, std::size_t nodes, std::size_t boundary_nodes,
                         std::uint64_t field_bytes, std::size_t real_bytes, int entries_per_node = kInitialStride,
                         bool momentum = false);

struct StepProgram;

// The device-resident run as a Simulator (the contract of sim/simulation.hpp). Same contract as
// run_simulation: updates nodes, returns the history; starts from options.resume when set (a SimState:
// everything is uploaded from the host at the start, so a run can begin from any node set and state).
// Throws InputError when options.exact_spacing is set (the device reads the background field) or
// options.metric is (no metric mode in the device-resident loop yet: the host driver runs metric runs),
// LimitError from check_device_memory (before the first allocation, and when the neighbour rows grow
// past what the device allows). Any error after the setup first hands the last good state to
// callbacks.on_failure; an OpenCL error is rethrown as DeviceError "iteration K: <call> failed: CL_NAME (code)".
class DeviceSimulator final : public Simulator {
 public:
  // Builds the step program on ctx (which must outlive this) now, so that a DeviceError from the build
  // or from the work-group check (StepProgram) comes before anything runs: a caller that picked the
  // device itself can try the next one. `loop`: the force loop's shape (Auto: by the device type or
  // PDMESH_FORCE_LOOP; step_program.hpp).
  DeviceSimulator(Context& ctx, Precision precision, ForceLoop loop = ForceLoop::Auto);
  ~DeviceSimulator() override;
  std::string describe() const override;
  SimResult run(NodeSet& nodes, const GeometryTree& tree, const SpacingField& spacing, const SimOptions& options,
                const SimCallbacks& callbacks = {}) override;
  // Of the last run.
  const DeviceRunStats& stats() const { return stats_; }
  Precision precision() const;
  ForceLoop force_loop() const;  // as built: Vector or Scalar

 private:
  Context& ctx_;
  std::unique_ptr<StepProgram> program_;
  DeviceRunStats stats_;
};

// The run itself on a built program (what DeviceSimulator::run calls after its checks; device_simulation.cpp).
SimResult run_device_resident(NodeSet& nodes, const GeometryTree& tree, const SpacingField& spacing,
                              const SimOptions& options, Context& ctx, StepProgram& program,
                              const SimCallbacks& callbacks, DeviceRunStats& stats);

// One run on a DeviceSimulator built for it (tests, bench).
SimResult run_device_simulation(NodeSet& nodes, const GeometryTree& tree, const SpacingField& spacing,
                                const SimOptions& options, Context& ctx, Precision precision = Precision::Double,
                                const SimCallbacks& callbacks = {}, DeviceRunStats* stats = nullptr,
                                ForceLoop loop = ForceLoop::Auto);

}  // namespace pdmesh::ocl
