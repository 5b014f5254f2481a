// The simulation's iteration loop shared by both drivers; see iteration_loop.hpp.
#include "sim/iteration_loop.hpp"

#include <chrono>
#include <cmath>
#include <memory>
#include <utility>

#include <fmt/format.h>

#include "core/cpu_time.hpp"
#include "core/errors.hpp"
#include "core/free_memory.hpp"
#include "core/interrupt.hpp"

namespace pdmesh {
namespace {

// The most nodes for which an event keeps its triangulation for the measurement after it.
constexpr std::size_t kKeepTriangulationNodes = std::size_t{1} << 18;

// The run's initial dt_GM: given, or from the default rule; a resumed run's own (checked first all the same).
double initial_dt(const NodeSet& nodes, const SimOptions& options) {
  const double dt = options.dt_initial ? *options.dt_initial : default_dt_initial(nodes, options.lj_a);
  if (!(dt > 0.0) || !std::isfinite(dt))
    throw InputError(fmt::format("simulation.dt_initial must be a positive number, got {}", dt));
  return options.resume ? options.resume->dt_initial : dt;
}

SimResult initial_result(const NodeSet& nodes, const SimOptions& options) {
  SimResult result;
  result.stats.dt_initial = initial_dt(nodes, options);
  result.history.reserve(history_reserve(options.iterations));
  if (options.resume) result.history = options.resume->history;
  return result;
}

}  // namespace

IterationLoop::IterationLoop(const NodeSet& nodes, const SimOptions& options)
    : nodes_(nodes),
      options_(options),
      result_(initial_result(nodes, options)),
      gm_(options.resume ? GlobalTimeStep(options.resume->time_step) : GlobalTimeStep(result_.stats.dt_initial)),
      convergence_(options.convergence, options.resume ? options.resume->convergence : std::vector<MeshSample>{}),
      done_(options.resume ? options.resume->iterations_done : 0),
      anneal_from_(metric_anneal_from(options)) {
  if (options.resume) population_.schedule = options.resume->population;
}

SimState IterationLoop::state(const BoundaryHandler& boundary, bool with_history) const {
  return SimState{done_,
                  result_.stats.dt_initial,
                  gm_.state(),
                  boundary.arcs(),
                  boundary.tangents(),
                  with_history ? result_.history : std::vector<HistoryRow>{},
                  population_.schedule,
                  convergence_.samples(),
                  {}};
}

SimResult IterationLoop::run(IterationSteps& steps, const SimCallbacks& callbacks, FailureScope scope) {
  callbacks_ = &callbacks;
  scope_ = scope;
  result_.stats.backend = steps.backend_name();
  progress_.emplace(options_.quiet);
  const auto start = std::chrono::steady_clock::now();
  iteration_ = done_ + 1;
  try {
    resume_checks();
    for (; iteration_ <= options_.iterations && !result_.converged; ++iteration_)
      if (!run_iteration(steps, iteration_)) break;
    progress_->finish();
    in_loop_ = false;
    steps.after_iterations();
  } catch (const DeviceError& e) {
    if (scope_ != FailureScope::Run) throw;
    fail(steps, e);
  } catch (const Error&) {
    if (scope_ == FailureScope::Run) {
      progress_->finish();
      hand_over(steps);
    }
    throw;
  }
  result_.stats.inserted = population_.inserted;
  result_.stats.removed = population_.removed;
  result_.stats.population_events = population_.events;
  result_.stats.population_seconds = population_.seconds;
  steps.end_run(result_);
  result_.stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return std::move(result_);
}

void IterationLoop::resume_checks() {
  if (!options_.resume) return;
  // A checkpoint written while the measurement after its last iteration was being taken (a stop
  // request ends the measurement) lacks it: taken now, so that the run goes on as if uninterrupted.
  if (convergence_.missing_sample(done_))
    convergence_.add_sample(options_.metric ? measure_mesh_in_metric(nodes_, done_, *options_.metric)
                                            : measure_mesh(nodes_, done_));
  // A run stopped in the iteration it converged in is complete (the uninterrupted run ended there).
  if (done_ < options_.iterations &&
      convergence_.converged_after(
          done_, population_status(options_.population, population_.schedule, done_, options_.iterations).settled,
          population_.schedule.last_change))
    result_.converged = true;
}

// A stop request ends the iteration's computation (neighbours, forces, moves: nothing has moved yet)
// with Interrupted, and the run stops after the previous one; once the nodes move the iteration runs
// whole (the shield) and the request is acted on after it (go_on).
bool IterationLoop::run_iteration(IterationSteps& steps, int iteration) {
  // In the global step's state, so that a checkpoint after this iteration resumes with it.
  if (anneal_from_ > 0 && iteration > anneal_from_) gm_.scale(options_.metric_anneal);
  const double dt_gm = gm_.dt();
  IterationStep step;
  try {
    step = compute_step(steps, iteration);
  } catch (const Interrupted&) {
    result_.stopped = true;  // the state after done(), as after a stop between iterations
    return false;
  }
  HistoryRow row;
  {
    const InterruptShield shield;
    // An event before a measurement keeps its triangulation for it (go_on). Not in a large run: the
    // triangulation would then live through the device's rebuild of the neighbour lists before the
    // measurement and add to that moment's peak, for a saving small beside such a run.
    population_.keep_triangulation =
        !options_.metric && convergence_.due(iteration) && nodes_.size() <= kKeepTriangulationNodes;
    const IterationMoves moves = steps.apply(iteration);
    row = record(iteration, dt_gm, step, moves);
    steps.after_row();
    // A population event's plan and read-backs are freed: their pages go back before the next build.
    if (moves.event) give_back_free_memory();
  }
  return go_on(steps, iteration, row);
}

IterationStep IterationLoop::compute_step(IterationSteps& steps, int iteration) {
  try {
    return steps.compute(iteration, gm_);
  } catch (const SimulationError&) {
    // Nothing has moved yet in this iteration: the node set still holds the last good state.
    if (scope_ == FailureScope::Step) hand_over(steps);
    throw;
  }
}

HistoryRow IterationLoop::record(int iteration, double dt_gm, const IterationStep& step, const IterationMoves& moves) {
  HistoryRow row;
  row.iteration = iteration;
  const double moving = step.sums.moving > 0 ? static_cast<double>(step.sums.moving) : 1.0;
  row.average_force = step.sums.sum_force / moving;
  row.average_kinetic = step.sums.sum_kinetic / moving;
  row.max_force = step.sums.max_force;
  row.dt_gm = dt_gm;
  row.snapped = moves.boundary.snapped;
  row.clamped = moves.boundary.clamped;
  row.fixed = moves.fixed;
  row.boundary = moves.on_boundary;
  row.interior = moves.interior;
  if (moves.event) {
    row.inserted = moves.event->inserted();
    row.removed = moves.event->removed();
  }
  gm_.update(step.sums.max_force);

  SimStats& stats = result_.stats;
  stats.pairs_examined += step.pairs_examined;
  stats.pairs_within += step.pairs_within;
  stats.coincident_pairs += step.coincident_pairs;
  stats.snapped += moves.boundary.snapped;
  result_.history.push_back(row);
  if (callbacks_->on_iteration) callbacks_->on_iteration(row);
  progress_->update(iteration, options_.iterations, row.average_force, dt_gm);
  done_ = iteration;
  return row;
}

// The nodes hold this iteration's positions: the stopping rule measures their mesh when due, also in
// an iteration the run is stopped after, so that a resumed run has every measurement.
bool IterationLoop::go_on(IterationSteps& steps, int iteration, const HistoryRow& row) {
  std::optional<MeshSample> sample;
  std::vector<std::array<int, 3>> measured;
  if (convergence_.due(iteration)) {
    const auto wall0 = std::chrono::steady_clock::now();
    const double cpu0 = thread_cpu_seconds();
    steps.before_measure(iteration, gm_);
    // The driver's part (a device run's read-back, and its rebuild when one is due) apart.
    const double wait = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
    // The measurement's triangulation is the run's largest transient: it starts without the free pages
    // of the builds and read-backs before it, and leaves none behind (core/free_memory.hpp).
    give_back_free_memory();
    // The measurement (a triangulation of every node) stops at a stop request: the state after this
    // iteration is whole, and a resumed run takes the measurement first (resume_checks).
    try {
      sample = options_.metric ? measure_mesh_in_metric(nodes_, iteration, *options_.metric)
                               : measure_mesh(nodes_, iteration, &measured, &population_.triangulation);
    } catch (const Interrupted&) {
      population_.triangulation.reset();
      steps.after_measure();
      result_.stopped = true;
      return false;
    }
    steps.after_measure();
    SimStats& stats = result_.stats;
    ++stats.measurements;
    stats.measure_wait_seconds += wait;
    stats.measure_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
    stats.measure_cpu_seconds += thread_cpu_seconds() - cpu0;
  }
  population_.triangulation.reset();
  // Never while population control may still change the node set.
  const bool settled =
      population_status(options_.population, population_.schedule, iteration, options_.iterations).settled;
  const bool converged =
      convergence_.observe(row, sample ? &*sample : nullptr, settled, population_.schedule.last_change);
  steps.after_observe();
  if (converged && iteration < options_.iterations) {
    result_.converged = true;
    if (!measured.empty())
      result_.final_mesh = std::make_shared<const Mesh>(measured_mesh(nodes_, std::move(measured)));
    return false;
  }
  if (sample) {
    std::vector<std::array<int, 3>>().swap(measured);
    give_back_free_memory();
  }
  if (options_.stop && options_.stop->load() && iteration < options_.iterations && steps.may_stop()) {
    result_.stopped = true;
    return false;
  }
  return true;
}

void IterationLoop::hand_over(IterationSteps& steps) {
  const SimState good = steps.failure_state();
  if (callbacks_->on_failure) callbacks_->on_failure(good);
}

// Where it failed, for the message; the error itself names the call and the CL code.
void IterationLoop::fail(IterationSteps& steps, const DeviceError& e) {
  progress_->finish();
  hand_over(steps);
  throw DeviceError(in_loop_ ? fmt::format("iteration {}: {}", iteration_, e.what())
                             : fmt::format("reading back the state after iteration {}: {}", done_, e.what()));
}

}  // namespace pdmesh
