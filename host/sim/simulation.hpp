// The particle dynamics simulation driver (thesis ch. 5): per iteration, neighbour lists, forces,
// local time steps and moves on a StepBackend, then boundary handling and the spacing update on the
// host, and the global maximum time step rule. Reproducible bit for bit on the reference backend.
#pragma once
#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "geometry/geometry_tree.hpp"
#include "nodes/node_set.hpp"
#include "sim/convergence.hpp"
#include "sim/global_time_step.hpp"
#include "sim/history.hpp"
#include "sim/population.hpp"
#include "sim/step_backend.hpp"
#include "sim/verlet_skin.hpp"
#include "spacing/spacing_field.hpp"

namespace pdmesh {

class BackgroundSpacing;
class MetricField;

// The driver's state between iterations beyond the NodeSet itself: with the NodeSet, enough to
// continue a run bit-identically on the host reference (host/sim/checkpoint.hpp stores it).
struct SimState {
  int iterations_done = 0;
  double dt_initial = 0.0;                // the run's initial dt_GM (for the statistics)
  GlobalTimeStep::State time_step;        // the global maximum time step rule
  std::vector<std::vector<double>> arcs;  // BoundaryHandler arc positions, parallel to curve_nodes
  std::vector<Vec2> tangents;             // BoundaryHandler tangent per node
  std::vector<HistoryRow> history;        // rows 1 .. iterations_done
  PopulationSchedule population;          // population control's schedule (sim/population.hpp)
  std::vector<MeshSample> convergence;    // the stopping rule's measurements (sim/convergence.hpp)
  // With SimOptions::momentum > 0: each node's last move p_i (MomentumState); empty = all zero.
  std::vector<Vec2> momentum;
};

struct SimOptions {
  int iterations = 2000;  // the run's length, or with convergence.enabled the most it may take
  // The stopping rule (sim/convergence.hpp): disabled by default, so that every iteration runs.
  ConvergenceOptions convergence;
  std::optional<double> dt_initial;  // initial global maximum time step; empty: default_dt_initial()
  double cutoff = 1.5;               // cut-off distance factor (neighbours within cutoff * q_i)
  double lj_a = 15.0;                // a of eq. 5.11
  bool r0_any_direction = false;     // ForceParams::r0_any_direction (false = thesis eq. 5.3)
  double stability_factor = 0.0;     // ForceParams::stability_factor (0 = off, the thesis)
  // Heavy-ball beta in [0, 1) (StepBackend::apply_momentum, docs/simulation.md "Momentum"); 0 = off:
  // the thesis' gradient-descent move, and no momentum arithmetic at all.
  double momentum = 0.0;
  // mix in [0, 1) with momentum > 0: each node's carried move is turned towards its force before it is
  // added (p = (1 - mix) p + mix |p| F / |F|, StepBackend::apply_momentum); 0 = off, bit for bit the
  // plain heavy-ball move.
  double momentum_mix = 0.0;
  bool quiet = false;  // no progress line on stderr
  // false: the per-iteration spacing update reads a BackgroundSpacing built once from the given field
  // (tolerance 1e-3, docs/spacing.md); true: evaluate the given field exactly every iteration.
  bool exact_spacing = false;
  // Non-null (and exact_spacing false): the spacing update (host) or the device's field reads this
  // quadtree instead of one built from the given field (the spacing pipeline's, built once per run).
  const BackgroundSpacing* background = nullptr;
  StepBackend* backend = nullptr;    // host driver: the step implementation; nullptr: the reference backend
  double verlet_skin = kVerletSkin;  // device run: list radius cutoff q (1 + skin); 0 rebuilds every iteration
  // Device run: the longest a window of queued iterations may be expected to take, from the last
  // window's time per iteration. A stop request is acted on at the end of a window, so this bounds how
  // long Ctrl-C waits at any size; the window's length does not change the run's result.
  double window_seconds = 0.25;
  // Polled once after every iteration (both backends); when it reads true the run stops there,
  // with SimResult::stopped set. Set from a signal handler, so it must be lock-free.
  const std::atomic<bool>* stop = nullptr;
  // Non-null: continue from this state (the NodeSet passed must be the one saved with it) with
  // iterations resume->iterations_done + 1 .. iterations; dt_initial is then unused.
  const SimState* resume = nullptr;
  // Node insertion and removal during the run (off by default: the thesis keeps the count fixed).
  PopulationOptions population;
  // Non-null: a metric run (docs/metric-fields.md, "Particles in the metric"). The host driver sets every
  // node's metric (SimParticles::m11, m12, m22) to metric->at(position) before each step, so the step
  // backend runs in metric mode: pairs measured in the metric, sigma = 1 in metric units. The spacing
  // field still gives NodeSet::q (read by messages, not by the step). Boundary handling is unchanged
  // (it moves nodes along their curves by arc gaps, with no length scale). Population control measures
  // in the metric too (plan_metric_population_event, sigma = 1 in metric units). The device-resident
  // Simulator has no metric mode and refuses one (InputError). Null: isotropic.
  // The field is read from the driver's thread only (ExpressionMetricField is not thread-safe).
  const MetricField* metric = nullptr;
  // A metric run under the stopping rule (convergence.enabled) that has not stopped by
  // metric_anneal_from(options) multiplies dt_GM by this factor before every later iteration, so that
  // its nodes come to rest (docs/simulation.md, "Annealing a metric run"); 1 = off. A small re-mesh in
  // a metric that varies over its own element sizes (an adaptation loop's Hessian metric on a few
  // hundred vertices) does not settle at the step the dt_GM rule keeps: its nodes creep on through
  // configurations of about the same quality, and the rule's window never closes.
  double metric_anneal = 0.99;
};

// The iteration after which a metric run's dt_GM decays (SimOptions::metric_anneal): population
// control's last event (population_last_event), and no earlier than the earliest stop plus one window;
// 0 (none) for an isotropic run, a run without the stopping rule, or metric_anneal = 1.
int metric_anneal_from(const SimOptions& options);

struct SimCallbacks {
  // After every iteration, with that iteration's history row.
  std::function<void(const HistoryRow&)> on_iteration;
  // Called with the last good state (the NodeSet passed to run_simulation then holds it) just before
  // an error from the iterations propagates, so that the caller can save a checkpoint. Host
  // reference: a SimulationError from the neighbour build or for non-finite forces or moves (not one
  // from boundary handling itself, which has moved nodes). Device run: any pdmesh::Error after the
  // setup (OpenCL errors included); the state is the one after the last complete iteration when the
  // device can still be read, else the one saved at the last neighbour-list build.
  std::function<void(const SimState&)> on_failure;
};

struct SimStats {
  std::string backend;
  double dt_initial = 0.0;           // the initial dt_GM used (given or from the default rule)
  double seconds = 0.0;              // wall time of the iterations
  std::uint64_t pairs_examined = 0;  // candidate pairs tested by the neighbour builds, all iterations
  std::uint64_t pairs_within = 0;    // pair interactions (interior neighbour-list entries), all iterations
  std::uint64_t coincident_pairs = 0;
  std::size_t snapped = 0;                // interior nodes snapped onto curves, all iterations
  std::size_t inserted = 0, removed = 0;  // by population control, all events of this run
  int population_events = 0;              // events run (including those that changed nothing)
  double population_seconds = 0.0;        // wall time of the events (planning and editing the node set)
  int measurements = 0;                   // the stopping rule's measurements of the mesh
  double measure_seconds = 0.0;           // their wall time: the driver's read-back and the triangulation
  double measure_cpu_seconds = 0.0;       // the CPU time of the thread that measured (not the shapes' workers)
  // Of measure_seconds, the driver's part before the triangulation (IterationSteps::before_measure: the
  // device run's read-back, and the neighbour build it makes before running ahead when one is due).
  double measure_wait_seconds = 0.0;
  // The driver's own split of the iterations' wall time, by name for the timings file (the device run:
  // its steps, neighbour builds, the host's exact test, transfers, population events); empty for the host.
  std::vector<std::pair<std::string, double>> split;
};

struct SimResult {
  std::vector<HistoryRow> history;  // every row, including those of a resumed run's earlier part
  SimStats stats;
  bool stopped = false;    // SimOptions::stop ended the run early
  bool converged = false;  // the convergence rule ended the run (before SimOptions::iterations)
  SimState state;          // the state after the last iteration run (history included)
  // A converged run: the mesh the rule measured in its last iteration, i.e. the final nodes'
  // triangulation (measure_mesh: curves named c0, c1, ...), which the mesh stage need not repeat.
  std::shared_ptr<const Mesh> final_mesh;
};

// The default initial dt_GM: a node at r = 0.9 sigma from one neighbour with the median interior
// spacing q should move q/200 in one step: dt^2 = 2 (q/200) / |f(0.9 q)|. Because f scales with
// sigma, q cancels: dt = sqrt((1/100) / (4 a g)), g = 0.9^-12 - 0.9^-6, i.e. 0.0100 for a = 15
// (the thesis' 0.01 for circle_circle; see docs/simulation.md for the calibration).
double default_dt_initial(const NodeSet& nodes, double lj_a);

// How many history rows to reserve for a run of `iterations` (capped: rows are added as they come).
std::size_t history_reserve(int iterations);

// SimState::momentum to and from the driver's MomentumState (n nodes; an empty saved list is all zero).
// momentum_from_state throws SimulationError when a non-empty list does not have n entries.
void momentum_from_state(const std::vector<Vec2>& saved, std::size_t n, MomentumState& carried);
std::vector<Vec2> momentum_to_state(const MomentumState& carried, std::size_t n);

// Throws SimulationError when the node set's arrays differ in length (every Simulator checks first).
void check_node_set(const NodeSet& nodes);

// Both drivers, before the run: the row locality trace (sim/row_locality.hpp) of a fresh run (no
// options.resume) with population control on; the events trace theirs.
void trace_nodes_at_start(const NodeSet& nodes, const SimOptions& options);

// The simulation contract: one whole run, whatever computes it. Implemented by the host driver below
// (make_host_simulator: run_simulation over a StepBackend) and by the device-resident run
// (host/opencl/device_simulation.hpp: ocl::DeviceSimulator); the app chooses one (app/pipeline/backend_choice),
// so sim/ knows nothing of OpenCL. run() has run_simulation's contract: it runs options.iterations
// iterations (or the remaining ones of options.resume, a SimState from a checkpoint or an earlier run),
// updates nodes in place, hands the last good state to callbacks.on_failure before an error propagates,
// and returns the history and the state reached.
class Simulator {
 public:
  virtual ~Simulator() = default;
  // Where the run computes, for messages: "the host reference (double)", "opencl:0:0 (..., double, device-resident)".
  virtual std::string describe() const = 0;
  virtual SimResult run(NodeSet& nodes, const GeometryTree& tree, const SpacingField& spacing,
                        const SimOptions& options, const SimCallbacks& callbacks = {}) = 0;
};

// The host driver as a Simulator (run_simulation).
std::unique_ptr<Simulator> make_host_simulator();
// The host driver over `backend` (owned; e.g. the OpenCL StepBackend), which it sets as
// SimOptions::backend of every run; describe() returns `description`.
std::unique_ptr<Simulator> make_host_simulator(std::unique_ptr<StepBackend> backend, std::string description);

// options.background, or a BackgroundSpacing of `spacing` built into `own` (default options).
const BackgroundSpacing& background_for(const SimOptions& options, const SpacingField& spacing,
                                        const GeometryTree& tree, std::unique_ptr<BackgroundSpacing>& own);

// The host driver: runs options.iterations iterations (or the remaining ones of options.resume) on
// options.backend (the reference when null), updating nodes (positions, q, kinds, curve_nodes) in place.
// Throws SimulationError on non-finite forces or moves, before anything moves in that iteration,
// naming the iteration, the node and its neighbourhood (callbacks.on_failure gets the last good state).
SimResult run_simulation(NodeSet& nodes, const GeometryTree& tree, const SpacingField& spacing,
                         const SimOptions& options, const SimCallbacks& callbacks = {});

}  // namespace pdmesh
