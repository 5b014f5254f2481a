// The simulation driver; see simulation.hpp and docs/simulation.md.
#include "sim/simulation.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <optional>

#include <fmt/format.h>

#include "core/errors.hpp"
#include "core/interrupt.hpp"
#include "sim/boundary_handling.hpp"
#include "sim/failure_report.hpp"
#include "sim/global_time_step.hpp"
#include "sim/progress.hpp"
#include "sim/step_trace.hpp"
#include "spacing/background_field.hpp"

namespace pdmesh {
namespace {

// Copies the node set into the backend's arrays.
void load_particles(const NodeSet& nodes, const BoundaryHandler& boundary, SimParticles& p) {
  const std::size_t n = nodes.size();
  p.resize(n);
  std::vector<int> prev, next;
  boundary.curve_neighbours(nodes, prev, next);
  for (std::size_t i = 0; i < n; ++i) {
    p.x[i] = nodes.x[i].x;
    p.y[i] = nodes.x[i].y;
    p.q[i] = nodes.q[i];
    p.kind[i] = static_cast<std::uint8_t>(nodes.kind[i]);
    p.prev[i] = prev[i];
    p.next[i] = next[i];
    const Vec2 t = boundary.tangent(static_cast<int>(i));
    p.tx[i] = t.x;
    p.ty[i] = t.y;
  }
}

}  // namespace

void check_node_set(const NodeSet& nodes) {
  const std::size_t n = nodes.size();
  if (nodes.q.size() != n || nodes.kind.size() != n || nodes.curve.size() != n)
    throw SimulationError(fmt::format("inconsistent node set: {} positions, {} spacings, {} kinds, {} curves", n,
                                      nodes.q.size(), nodes.kind.size(), nodes.curve.size()));
}

void momentum_from_state(const std::vector<Vec2>& saved, std::size_t n, MomentumState& carried) {
  carried.px.assign(n, 0.0);
  carried.py.assign(n, 0.0);
  if (saved.empty()) return;
  if (saved.size() != n)
    throw SimulationError(fmt::format("the saved momentum has {} entries for {} nodes", saved.size(), n));
  for (std::size_t i = 0; i < n; ++i) {
    carried.px[i] = saved[i].x;
    carried.py[i] = saved[i].y;
  }
}

std::vector<Vec2> momentum_to_state(const MomentumState& carried, std::size_t n) {
  std::vector<Vec2> out(n, Vec2{0.0, 0.0});
  for (std::size_t i = 0; i < n && i < carried.px.size(); ++i) out[i] = {carried.px[i], carried.py[i]};
  return out;
}

namespace {

// The first node with a non-finite force or move component (the node count if none).
std::size_t first_non_finite(const ForceResult& forces, const MoveResult& moves) {
  const std::size_t n = moves.dx.size();
  for (std::size_t i = 0; i < n; ++i)
    if (!std::isfinite(forces.fx[i]) || !std::isfinite(forces.fy[i]) || !std::isfinite(moves.dx[i]) ||
        !std::isfinite(moves.dy[i]))
      return i;
  return n;
}

// The default dt moves a node at 0.9 sigma by this fraction of q (calibrated: docs/simulation.md).
constexpr double kDefaultMoveFraction = 1.0 / 200.0;

}  // namespace

std::size_t history_reserve(int iterations) {
  // A row is 80 bytes; --iterations 2000000000 must not ask for 160 GB before the first iteration.
  return static_cast<std::size_t>(std::clamp(iterations, 0, 1 << 20));
}

double default_dt_initial(const NodeSet& nodes, double lj_a) {
  std::vector<double> q;
  for (std::size_t i = 0; i < nodes.size(); ++i)
    if (nodes.kind[i] == NodeKind::Interior) q.push_back(nodes.q[i]);
  if (q.empty()) q = nodes.q;
  double median = 1.0;
  if (!q.empty()) {
    std::nth_element(q.begin(), q.begin() + static_cast<std::ptrdiff_t>(q.size() / 2), q.end());
    median = q[q.size() / 2];
  }
  // |f(r)| = 4 a sigma ((sigma/r)^12 - (sigma/r)^6) at r = 0.9 sigma, sigma = median.
  const double s6 = std::pow(1.0 / 0.9, 6);
  const double force = 4.0 * lj_a * median * (s6 * s6 - s6);
  return std::sqrt(2.0 * (median * kDefaultMoveFraction) / force);
}

const BackgroundSpacing& background_for(const SimOptions& options, const SpacingField& spacing, const GeometryTree& tree,
                                        std::unique_ptr<BackgroundSpacing>& own) {
  if (options.background) return *options.background;
  own = std::make_unique<BackgroundSpacing>(spacing, tree);
  return *own;
}

SimResult run_simulation(NodeSet& nodes, const GeometryTree& tree, const SpacingField& spacing,
                         const SimOptions& options, const SimCallbacks& callbacks) {
  check_node_set(nodes);
  std::unique_ptr<StepBackend> own_backend;
  StepBackend* backend = options.backend;
  if (!backend) {
    own_backend = make_reference_backend();
    backend = own_backend.get();
  }
  SimResult result;
  result.stats.backend = backend->name();
  result.stats.dt_initial = options.dt_initial ? *options.dt_initial : default_dt_initial(nodes, options.lj_a);
  if (!(result.stats.dt_initial > 0.0) || !std::isfinite(result.stats.dt_initial))
    throw InputError(fmt::format("simulation.dt_initial must be a positive number, got {}", result.stats.dt_initial));
  const SimState* resume = options.resume;
  if (resume) result.stats.dt_initial = resume->dt_initial;
  GlobalTimeStep gm = resume ? GlobalTimeStep(resume->time_step) : GlobalTimeStep(result.stats.dt_initial);
  BoundaryHandler boundary(tree, nodes);
  if (resume) boundary.restore(nodes, resume->arcs, resume->tangents);
  // The exact field costs microseconds per node (eq. 3.6 queries every curve); the background field
  // a lookup, so it is built once here and read every iteration.
  std::unique_ptr<BackgroundSpacing> own_background;
  const SpacingField& iteration_spacing =
      options.exact_spacing ? spacing : static_cast<const SpacingField&>(background_for(options, spacing, tree, own_background));
  ProgressLine progress(options.quiet);
  const auto start = std::chrono::steady_clock::now();

  SimParticles particles;
  NeighbourList list;
  NeighbourFlags flags;
  ForceResult forces;
  MoveResult moves;
  const TraceRange trace = TraceRange::from_environment();
  ForceParams params{options.cutoff, options.lj_a, options.r0_any_direction, options.stability_factor};
  result.history.reserve(history_reserve(options.iterations));
  if (resume) result.history = resume->history;
  const int first = resume ? resume->iterations_done + 1 : 1;
  int done = first - 1;
  PopulationTracker population;
  if (resume) population.schedule = resume->population;
  ConvergenceMonitor convergence(options.convergence, resume ? resume->convergence : std::vector<MeshSample>{});
  // The state after `done` iterations; nodes must hold that iteration's positions.
  // Heavy-ball momentum (options.momentum > 0 only): each node's last move, carried into the next.
  const bool with_momentum = options.momentum > 0.0;
  MomentumState carried;
  if (with_momentum && resume) momentum_from_state(resume->momentum, nodes.size(), carried);
  const auto snapshot = [&] {
    SimState s{done,           result.stats.dt_initial, gm.state(),
               boundary.arcs(), boundary.tangents(),    result.history,
               population.schedule, convergence.samples(), {}};
    if (with_momentum) s.momentum = momentum_to_state(carried, nodes.size());
    return s;
  };
  // A checkpoint written while the measurement after its last iteration was being taken (a stop
  // request ends the measurement) lacks it: taken now, so that the run goes on as if uninterrupted.
  if (resume && convergence.missing_sample(done)) convergence.add_sample(measure_mesh(nodes, done));
  // A run stopped in the iteration it converged in is complete (the uninterrupted run ended there).
  if (resume && done < options.iterations &&
      convergence.converged_after(
          done, population_status(options.population, population.schedule, done, options.iterations).settled))
    result.converged = true;
  for (int iteration = first; iteration <= options.iterations && !result.converged; ++iteration) {
    const double dt_gm = gm.dt();
    // A stop request ends the iteration's computation (neighbours, forces, moves: nothing has moved
    // yet) with Interrupted, and the run stops after the previous one; once the nodes move the
    // iteration runs whole (the shield below) and the request is acted on after it.
    std::optional<InterruptShield> shield;
    StepSums sums;
    try {
      load_particles(nodes, boundary, particles);
      build_neighbours_growing(*backend, particles, options.cutoff, list, flags);
      backend->compute_forces(particles, list, params, forces);
      backend->time_step_and_move(particles, forces, gm.dt2(), moves);
      // On a copy: a failure below must leave the last good iteration's p for the checkpoint.
      MomentumState next_carried;
      if (with_momentum) {
        next_carried = carried;
        backend->apply_momentum(particles, forces, options.momentum, moves, next_carried);
      }
      sums = backend->reduce(particles, forces, moves);
      if (trace.covers(iteration))
        trace_step(stderr, iteration, particles, list, forces, moves, gm.dt2(), options.cutoff, 3);
      // Before boundary handling moves anything: a non-finite move would otherwise be turned into a
      // non-finite position there (boundary nodes) or stop it half done (interior nodes).
      const std::size_t bad = first_non_finite(forces, moves);
      if (bad < nodes.size() || !std::isfinite(sums.sum_force) || !std::isfinite(sums.sum_kinetic)) {
        if (bad >= nodes.size())
          throw SimulationError(fmt::format("iteration {}: the force sums overflowed (sum |F| {}, sum kinetic {})",
                                            iteration, sums.sum_force, sums.sum_kinetic));
        const bool force = !std::isfinite(forces.fx[bad]) || !std::isfinite(forces.fy[bad]);
        throw SimulationError(fmt::format("iteration {}: non-finite {} (force ({}, {}), move ({}, {})) on {}",
                                          iteration, force ? "force" : "move", forces.fx[bad], forces.fy[bad],
                                          moves.dx[bad], moves.dy[bad],
                                          describe_neighbourhood(nodes, bad, options.cutoff * nodes.q[bad])));
      }
      if (with_momentum) carried = std::move(next_carried);
    } catch (const SimulationError&) {
      // Nothing has moved yet in this iteration: the nodes still hold the last good state.
      if (callbacks.on_failure) callbacks.on_failure(snapshot());
      throw;
    } catch (const Interrupted&) {
      result.stopped = true;  // the state after `done`, as after a stop between iterations
      break;
    }
    shield.emplace();
    const BoundaryCounts counts = boundary.apply(nodes, moves.dx, moves.dy);
    // An interior node snapped onto a curve is a boundary node now: its interior motion does not carry
    // over (the device run does the same in host_boundary).
    if (with_momentum && counts.snapped > 0)
      for (std::size_t i = 0; i < particles.size(); ++i)
        if (static_cast<std::uint8_t>(nodes.kind[i]) != particles.kind[i]) carried.px[i] = carried.py[i] = 0.0;
    iteration_spacing.at_many(nodes.x, nodes.q);
    // Population control between iterations: the next iteration loads the changed node set.
    const auto event =
        population.after_iteration(options.population, iteration, options.iterations, nodes, boundary, iteration_spacing);

    // A changed node set starts without momentum (nodes were inserted, removed and renumbered).
    if (with_momentum && event && event->changed()) carried = MomentumState{};

    HistoryRow row;
    row.iteration = iteration;
    const double moving = sums.moving > 0 ? static_cast<double>(sums.moving) : 1.0;
    row.average_force = sums.sum_force / moving;
    row.average_kinetic = sums.sum_kinetic / moving;
    row.max_force = sums.max_force;
    row.dt_gm = dt_gm;
    row.snapped = counts.snapped;
    row.clamped = counts.clamped;
    row.fixed = nodes.count(NodeKind::Fixed);
    row.boundary = nodes.count(NodeKind::Boundary);
    row.interior = nodes.count(NodeKind::Interior);
    if (event) {
      row.inserted = event->inserted();
      row.removed = event->removed();
    }
    gm.update(sums.max_force);

    result.stats.pairs_examined += flags.pairs_examined;
    result.stats.pairs_within += flags.pairs_within;
    result.stats.coincident_pairs += forces.coincident_pairs;
    result.stats.snapped += counts.snapped;
    result.history.push_back(row);
    if (callbacks.on_iteration) callbacks.on_iteration(row);
    progress.update(iteration, options.iterations, row.average_force, dt_gm);
    done = iteration;
    // The nodes hold this iteration's positions: the stopping rule measures their mesh when due, also
    // in an iteration the run is stopped after, so that a resumed run has every measurement.
    std::optional<MeshSample> sample;
    Mesh measured;
    shield.reset();
    if (convergence.due(iteration)) {
      // The measurement (a triangulation of every node) stops at a stop request: the state after this
      // iteration is whole, and a resumed run takes the measurement first (missing_sample above).
      try {
        sample = measure_mesh(nodes, iteration, &measured);
      } catch (const Interrupted&) {
        result.stopped = true;
        break;
      }
    }
    // Never while population control may still change the node set.
    const bool settled = population_status(options.population, population.schedule, iteration, options.iterations).settled;
    if (convergence.observe(row, sample ? &*sample : nullptr, settled) && iteration < options.iterations) {
      result.converged = true;
      if (!measured.triangles.empty()) result.final_mesh = std::make_shared<const Mesh>(std::move(measured));
      break;
    }
    if (options.stop && options.stop->load() && iteration < options.iterations) {
      result.stopped = true;
      break;
    }
  }
  progress.finish();
  result.stats.inserted = population.inserted;
  result.stats.removed = population.removed;
  result.stats.population_events = population.events;
  result.stats.population_seconds = population.seconds;
  result.state = snapshot();
  result.stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

namespace {

class HostSimulator final : public Simulator {
 public:
  std::string describe() const override { return "the host reference (double)"; }
  SimResult run(NodeSet& nodes, const GeometryTree& tree, const SpacingField& spacing, const SimOptions& options,
                const SimCallbacks& callbacks) override {
    return run_simulation(nodes, tree, spacing, options, callbacks);
  }
};

}  // namespace

std::unique_ptr<Simulator> make_host_simulator() { return std::make_unique<HostSimulator>(); }

}  // namespace pdmesh
