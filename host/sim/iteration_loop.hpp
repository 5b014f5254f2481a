// The simulation's iteration loop, written once for both drivers: the host driver (run_simulation,
// sim/simulation.cpp) and the device-resident run (host/opencl/device_simulation.cpp), which replays
// each row of a window of device iterations through this same loop. IterationLoop owns what every run
// keeps between iterations and does with each one: the initial dt_GM and the global maximum time step
// rule, a resumed run's state, the history rows, the statistics both drivers share, population
// control's schedule, the stopping rule (its measurements and the resumed run's checks), the stop
// request, the progress line, the interrupt shield of an iteration's moves and the hand-over of the
// last good state on failure. The driver supplies the iteration's computation and moves through
// IterationSteps.
#pragma once
#include <cstdint>
#include <optional>
#include <string>

#include "core/errors.hpp"
#include "nodes/node_set.hpp"
#include "sim/boundary_handling.hpp"
#include "sim/convergence.hpp"
#include "sim/global_time_step.hpp"
#include "sim/population.hpp"
#include "sim/progress.hpp"
#include "sim/simulation.hpp"
#include "sim/step_backend.hpp"

namespace pdmesh {

// What an iteration's computation (IterationSteps::compute) hands the history row and the statistics.
struct IterationStep {
  StepSums sums;                       // over the moving nodes, before the move
  std::uint64_t pairs_examined = 0;    // SimStats::pairs_examined of this iteration
  std::uint64_t pairs_within = 0;      // SimStats::pairs_within of this iteration
  std::uint64_t coincident_pairs = 0;  // SimStats::coincident_pairs of this iteration
};

// What an iteration's moves (IterationSteps::apply) did: boundary handling, population control after
// it, and the node counts by kind that leaves.
struct IterationMoves {
  BoundaryCounts boundary;
  std::optional<PopulationCounts> event;  // the population event after the iteration, when one ran
  std::size_t fixed = 0, on_boundary = 0, interior = 0;
};

// The driver's part of an iteration and of the run's end; IterationLoop calls them in this order.
class IterationSteps {
 public:
  virtual ~IterationSteps() = default;
  // Where the run computes (SimStats::backend).
  virtual std::string backend_name() const = 0;
  // The iteration's computation up to its moves, nothing moved yet: neighbours, forces, moves and their
  // sums at gm.dt(). May throw Interrupted (the run then stops after the previous iteration).
  virtual IterationStep compute(int iteration, const GlobalTimeStep& gm) = 0;
  // The moves applied: boundary handling, the spacing update and population control
  // (IterationLoop::population). Runs whole: a stop request waits until the iteration is done.
  virtual IterationMoves apply(int iteration) = 0;
  // After the iteration's row is recorded (IterationLoop::done() is the iteration).
  virtual void after_row() {}
  // Before the stopping rule measures the mesh after `iteration`: the node set must hold its positions.
  virtual void before_measure(int /*iteration*/, const GlobalTimeStep& /*gm*/) {}
  // Right after the measurement (taken, or ended by a stop request), before the stopping rule sees it:
  // a driver that worked on while the host measured stops there.
  virtual void after_measure() {}
  // After the stopping rule has seen the iteration (measured or not).
  virtual void after_observe() {}
  // Whether a stop request may end the run after the iteration just done.
  virtual bool may_stop() const { return true; }
  // After the last iteration run (or a stop): the node set must hold the state after done().
  virtual void after_iterations() {}
  // The last good state, for SimCallbacks::on_failure (the node set must then hold it).
  virtual SimState failure_state() = 0;
  // The run's end: result.state and what else the driver adds to the result.
  virtual void end_run(SimResult& result) = 0;
};

// Which errors hand the last good state to SimCallbacks::on_failure (see there).
enum class FailureScope {
  Step,  // a SimulationError from IterationSteps::compute only (the host driver: nothing has moved yet)
  Run,   // any Error after the setup; a DeviceError is rethrown naming the iteration (the device run)
};

class IterationLoop {
 public:
  // The run's initial dt_GM (options.dt_initial or default_dt_initial; a resumed run's own), checked;
  // the time step rule, population schedule, stopping rule and history of options.resume when set.
  // Throws InputError when the initial dt_GM is not a positive number.
  IterationLoop(const NodeSet& nodes, const SimOptions& options);

  // Runs iterations done() + 1 .. options.iterations (fewer when the run converges or is stopped).
  SimResult run(IterationSteps& steps, const SimCallbacks& callbacks, FailureScope scope);

  int done() const { return done_; }  // iterations complete (a resumed run's earlier ones included)
  double dt_initial() const { return result_.stats.dt_initial; }
  const GlobalTimeStep& time_step() const { return gm_; }
  const std::vector<HistoryRow>& history() const { return result_.history; }
  PopulationTracker& population() { return population_; }
  const ConvergenceMonitor& convergence() const { return convergence_; }
  // The run's state after done() with the boundary handler's arcs and tangents (momentum empty): every
  // history row, or none (with_history false).
  SimState state(const BoundaryHandler& boundary, bool with_history = true) const;

 private:
  // A resumed run: the measurement a stop request ended, then whether it had converged already.
  void resume_checks();
  // One iteration; false when the run ends after it (or, stopped, before it).
  bool run_iteration(IterationSteps& steps, int iteration);
  // The driver's computation; a SimulationError from it hands the last good state over (FailureScope::Step).
  IterationStep compute_step(IterationSteps& steps, int iteration);
  // The iteration's history row into the history, the statistics, the callback and the progress line.
  HistoryRow record(int iteration, double dt_gm, const IterationStep& step, const IterationMoves& moves);
  // The stopping rule and the stop request after `iteration`; false when the run ends there.
  bool go_on(IterationSteps& steps, int iteration, const HistoryRow& row);
  void hand_over(IterationSteps& steps);
  [[noreturn]] void fail(IterationSteps& steps, const DeviceError& e);

  const NodeSet& nodes_;
  const SimOptions& options_;
  const SimCallbacks* callbacks_ = nullptr;
  FailureScope scope_ = FailureScope::Step;
  SimResult result_;
  GlobalTimeStep gm_;
  PopulationTracker population_;
  ConvergenceMonitor convergence_;
  std::optional<ProgressLine> progress_;  // from the start of run()
  int done_ = 0;
  int anneal_from_ = 0;  // metric_anneal_from(options_)
  int iteration_ = 0;    // the iteration under way (for a failure's message)
  bool in_loop_ = true;  // false once the iterations are done (the final read-back)
};

}  // namespace pdmesh
