// The simulation driver; see simulation.hpp and docs/simulation.md.
#include "sim/simulation.hpp"

#include <algorithm>
#include <cmath>
#include <memory>

#include <fmt/format.h>

#include "core/errors.hpp"
#include "sim/boundary_handling.hpp"
#include "sim/failure_report.hpp"
#include "sim/iteration_loop.hpp"
#include "sim/population_profile.hpp"
#include "sim/row_locality.hpp"
#include "sim/step_trace.hpp"
#include "spacing/background_field.hpp"
#include "spacing/metric_field.hpp"

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

// Metric mode: every node's metric at its position (the arrays cleared otherwise: isotropic mode);
// `guesses` is the field's memory of where the nodes were.
void load_metric(const NodeSet& nodes, const MetricField* metric, std::vector<int>& guesses, SimParticles& p) {
  if (!metric) {
    p.m11.clear();
    p.m12.clear();
    p.m22.clear();
    return;
  }
  const std::size_t n = nodes.size();
  std::vector<Metric> m;
  metric->at_many(nodes.x, m, guesses);
  p.m11.resize(n);
  p.m12.resize(n);
  p.m22.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    p.m11[i] = m[i].m11;
    p.m12[i] = m[i].m12;
    p.m22[i] = m[i].m22;
  }
}

}  // namespace

void check_node_set(const NodeSet& nodes) {
  const std::size_t n = nodes.size();
  if (nodes.q.size() != n || nodes.kind.size() != n || nodes.curve.size() != n)
    throw SimulationError(fmt::format("inconsistent node set: {} positions, {} spacings, {} kinds, {} curves", n,
                                      nodes.q.size(), nodes.kind.size(), nodes.curve.size()));
}

void trace_nodes_at_start(const NodeSet& nodes, const SimOptions& options) {
  if (!options.resume && options.population.enabled) trace_row_locality("at the start", nodes);
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

int metric_anneal_from(const SimOptions& options) {
  if (!options.metric || !options.convergence.enabled || !(options.metric_anneal < 1.0)) return 0;
  // From population control's last event on the node set is final: what is left is the creep the
  // decay ends (docs/simulation.md, "Annealing a metric run").
  return std::max(population_last_event(options.population, options.iterations),
                  options.convergence.min_iterations + options.convergence.window);
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

const BackgroundSpacing& background_for(const SimOptions& options, const SpacingField& spacing,
                                        const GeometryTree& tree, std::unique_ptr<BackgroundSpacing>& own) {
  if (options.background) return *options.background;
  own = std::make_unique<BackgroundSpacing>(spacing, tree);
  return *own;
}

namespace {

// The host driver's part of an iteration (IterationSteps): the step on a StepBackend from the node
// set's arrays, then boundary handling, the spacing update and population control on the node set.
// Heavy-ball momentum (options.momentum > 0 only): each node's last move, carried into the next.
class HostSteps final : public IterationSteps {
 public:
  HostSteps(NodeSet& nodes, const SimOptions& options, StepBackend& backend, BoundaryHandler& boundary,
            const SpacingField& spacing, IterationLoop& loop)
      : nodes_(nodes),
        options_(options),
        backend_(backend),
        boundary_(boundary),
        spacing_(spacing),
        loop_(loop),
        params_{options.cutoff, options.lj_a, options.r0_any_direction, options.stability_factor} {
    if (with_momentum_ && options.resume) momentum_from_state(options.resume->momentum, nodes.size(), carried_);
  }

  std::string backend_name() const override { return backend_.name(); }
  IterationStep compute(int iteration, const GlobalTimeStep& gm) override;
  IterationMoves apply(int iteration) override;
  SimState failure_state() override {
    if (options_.metric) refresh_spacing();
    return state();
  }
  void after_iterations() override {
    if (options_.metric) refresh_spacing();
  }
  void end_run(SimResult& result) override { result.state = state(); }

 private:
  // The state after loop_.done(); the node set must hold that iteration's positions.
  SimState state() const {
    SimState s = loop_.state(boundary_);
    if (with_momentum_) s.momentum = momentum_to_state(carried_, nodes_.size());
    return s;
  }
  // Every node's q from the spacing field at its position.
  void refresh_spacing() { spacing_.at_many_guessed(nodes_.x, nodes_.q, spacing_guesses_); }
  // Throws SimulationError naming the first node with a non-finite force or move, or the sums.
  void check_finite(int iteration, const StepSums& sums) const;

  NodeSet& nodes_;
  const SimOptions& options_;
  StepBackend& backend_;
  BoundaryHandler& boundary_;
  const SpacingField& spacing_;  // the per-iteration spacing update's field
  IterationLoop& loop_;
  const ForceParams params_;
  const TraceRange trace_ = TraceRange::from_environment();
  const bool with_momentum_ = options_.momentum > 0.0;
  MomentumState carried_;
  SimParticles particles_;
  std::vector<int> metric_guesses_, spacing_guesses_;
  NeighbourList list_;
  NeighbourFlags flags_;
  ForceResult forces_;
  MoveResult moves_;
};

IterationStep HostSteps::compute(int iteration, const GlobalTimeStep& gm) {
  load_particles(nodes_, boundary_, particles_);
  // Every step: the nodes moved (and population control may have changed the set) since the last.
  load_metric(nodes_, options_.metric, metric_guesses_, particles_);
  build_neighbours_growing(backend_, particles_, options_.cutoff, list_, flags_);
  backend_.compute_forces(particles_, list_, params_, forces_);
  backend_.time_step_and_move(particles_, forces_, gm.dt2(), moves_);
  // On a copy: a failure below must leave the last good iteration's p for the checkpoint.
  MomentumState next_carried;
  if (with_momentum_) {
    next_carried = carried_;
    backend_.apply_momentum(particles_, forces_, options_.momentum, options_.momentum_mix, moves_, next_carried);
  }
  const StepSums sums = backend_.reduce(particles_, forces_, moves_);
  if (trace_.covers(iteration))
    trace_step(stderr, iteration, particles_, list_, forces_, moves_, gm.dt2(), options_.cutoff, 3);
  check_finite(iteration, sums);
  if (with_momentum_) carried_ = std::move(next_carried);
  return IterationStep{sums, flags_.pairs_examined, flags_.pairs_within, forces_.coincident_pairs};
}

// Before boundary handling moves anything: a non-finite move would otherwise be turned into a
// non-finite position there (boundary nodes) or stop it half done (interior nodes).
void HostSteps::check_finite(int iteration, const StepSums& sums) const {
  const std::size_t bad = first_non_finite(forces_, moves_);
  if (bad >= nodes_.size() && std::isfinite(sums.sum_force) && std::isfinite(sums.sum_kinetic)) return;
  if (bad >= nodes_.size())
    throw SimulationError(fmt::format("iteration {}: the force sums overflowed (sum |F| {}, sum kinetic {})", iteration,
                                      sums.sum_force, sums.sum_kinetic));
  const bool force = !std::isfinite(forces_.fx[bad]) || !std::isfinite(forces_.fy[bad]);
  throw SimulationError(fmt::format("iteration {}: non-finite {} (force ({}, {}), move ({}, {})) on {}", iteration,
                                    force ? "force" : "move", forces_.fx[bad], forces_.fy[bad], moves_.dx[bad],
                                    moves_.dy[bad],
                                    describe_neighbourhood(nodes_, bad, options_.cutoff * nodes_.q[bad])));
}

IterationMoves HostSteps::apply(int iteration) {
  IterationMoves out;
  out.boundary = boundary_.apply(nodes_, moves_.dx, moves_.dy);
  // An interior node snapped onto a curve is a boundary node now: its interior motion does not carry
  // over (the device run does the same in host_boundary).
  if (with_momentum_ && out.boundary.snapped > 0)
    for (std::size_t i = 0; i < particles_.size(); ++i)
      if (static_cast<std::uint8_t>(nodes_.kind[i]) != particles_.kind[i]) carried_.px[i] = carried_.py[i] = 0.0;
  // A metric run's step reads the metric, not q (q only has to stay finite and positive, which the
  // last value is): its q is brought up to date once, when the run hands the nodes back.
  if (!options_.metric) refresh_spacing();
  // Population control between iterations: the next iteration loads the changed node set.
  out.event = loop_.population().after_iteration(options_.population, iteration, options_.iterations, nodes_, boundary_,
                                                 spacing_, nullptr, options_.metric);
  if (out.event) population_profile::print(fmt::format("after iteration {}", iteration).c_str());
  // A changed node set starts without momentum (nodes were inserted, removed and renumbered).
  if (with_momentum_ && out.event && out.event->changed()) carried_ = MomentumState{};
  out.fixed = nodes_.count(NodeKind::Fixed);
  out.on_boundary = nodes_.count(NodeKind::Boundary);
  out.interior = nodes_.count(NodeKind::Interior);
  return out;
}

}  // namespace

SimResult run_simulation(NodeSet& nodes, const GeometryTree& tree, const SpacingField& spacing,
                         const SimOptions& options, const SimCallbacks& callbacks) {
  check_node_set(nodes);
  trace_nodes_at_start(nodes, options);
  std::unique_ptr<StepBackend> own_backend;
  StepBackend* backend = options.backend;
  if (!backend) {
    own_backend = make_reference_backend();
    backend = own_backend.get();
  }
  IterationLoop loop(nodes, options);
  BoundaryHandler boundary(tree, nodes);
  if (options.resume) boundary.restore(nodes, options.resume->arcs, options.resume->tangents);
  // The exact field costs microseconds per node (eq. 3.6 queries every curve); the background field
  // a lookup, so it is built once here and read every iteration.
  std::unique_ptr<BackgroundSpacing> own_background;
  const SpacingField& iteration_spacing =
      options.exact_spacing ? spacing
                            : static_cast<const SpacingField&>(background_for(options, spacing, tree, own_background));
  HostSteps steps(nodes, options, *backend, boundary, iteration_spacing, loop);
  return loop.run(steps, callbacks, FailureScope::Step);
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

// The host driver over a step backend it owns.
class HostDrivenSimulator final : public Simulator {
 public:
  HostDrivenSimulator(std::unique_ptr<StepBackend> backend, std::string description)
      : backend_(std::move(backend)), description_(std::move(description)) {}
  std::string describe() const override { return description_; }
  SimResult run(NodeSet& nodes, const GeometryTree& tree, const SpacingField& spacing, const SimOptions& options,
                const SimCallbacks& callbacks) override {
    SimOptions with_backend = options;
    with_backend.backend = backend_.get();
    return run_simulation(nodes, tree, spacing, with_backend, callbacks);
  }

 private:
  std::unique_ptr<StepBackend> backend_;
  std::string description_;
};

}  // namespace

std::unique_ptr<Simulator> make_host_simulator() { return std::make_unique<HostSimulator>(); }

std::unique_ptr<Simulator> make_host_simulator(std::unique_ptr<StepBackend> backend, std::string description) {
  return std::make_unique<HostDrivenSimulator>(std::move(backend), std::move(description));
}

}  // namespace pdmesh
