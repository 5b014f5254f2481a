// `pdmesh mesh`, stage simulation (mesh_pipeline.hpp): the simulation settings of a case, and
// simulate(), which runs them on the chosen backend, keeps the checkpoint and writes the stage's outputs.
#include <filesystem>
#include <optional>
#include <fmt/format.h>

#include "app/pipeline/interrupt.hpp"
#include "app/pipeline/mesh_pipeline.hpp"
#include "app/pipeline/pipeline_detail.hpp"
#include "app/pipeline/resume.hpp"
#include "core/errors.hpp"
#include "core/interrupt.hpp"
#include "render/history_plot.hpp"

namespace pdmesh {

namespace fs = std::filesystem;
using mesh_detail::progress;
using mesh_detail::write_node_outputs;

SimOptions simulation_options(const CaseConfig& config, std::size_t nodes) {
  SimOptions options;
  options.iterations = static_cast<int>(config.simulation.iterations);
  options.convergence.enabled = config.simulation.stop == StopRule::Converged;
  options.convergence.aspect_tolerance = config.simulation.stop_aspect;
  options.convergence.angle_tolerance = config.simulation.stop_angle;
  options.convergence.check_every = config.simulation.stop_every;
  options.convergence.window = config.simulation.stop_window;
  options.convergence.min_iterations = config.simulation.stop_min;
  options.convergence.from_last_event = config.simulation.stop_from_event;
  options.metric_anneal = config.simulation.metric_anneal;
  options.dt_initial = config.simulation.dt_for(config.init.method);
  options.cutoff = config.simulation.cutoff;
  options.lj_a = config.simulation.lj_a;
  options.r0_any_direction = config.simulation.r0_any_direction;
  options.stability_factor = config.simulation.stability_factor;
  options.momentum = config.simulation.momentum;
  options.momentum_mix = config.simulation.momentum_mix;
  options.verlet_skin = config.simulation.verlet_skin.value_or(auto_verlet_skin(options.momentum, nodes));
  options.population = config.population;
  options.quiet = config.quiet;
  return options;
}

namespace {

// The first progress lines of the stage: the settings and the backend.
void announce(const CaseConfig& config, const SimOptions& options, const Simulator& simulator, const SimState* resume) {
  progress(config, "simulation: {}{} iterations on {}, cutoff {}, a = {}, r0 rule {}, stability factor {}{}",
           options.convergence.enabled ? "until converged, at most " : "", options.iterations, simulator.describe(),
           options.cutoff, options.lj_a, options.r0_any_direction ? "any_direction" : "force_direction",
           options.stability_factor,
           options.momentum > 0.0 ? fmt::format(", momentum {}", options.momentum) : std::string());
  if (resume) progress(config, "simulation: resuming after iteration {}", resume->iterations_done);
}

// The simulation itself on `backend`. A failure after a good state writes that state to the
// checkpoint (when outputs are written) and says so, and how to continue, in its message.
SimResult run_on_backend(const CaseConfig& config, const MeshInputs& inputs, const SpacingStage& spacing,
                         NodeSet& nodes, const SimOptions& options, const SimulateHooks* hooks,
                         const ChosenBackend& backend, RunPhases& phases) {
  const fs::path checkpoint_file = checkpoint_path(config.out_dir);
  SimCallbacks callbacks;
  if (config.stop_after > 0 || (hooks && hooks->on_iteration)) {
    callbacks.on_iteration = [&config, hooks](const HistoryRow& row) {
      if (config.stop_after > 0 && row.iteration == config.stop_after) InterruptGuard::flag().store(true);
      if (hooks && hooks->on_iteration) hooks->on_iteration(row);
    };
  }
  std::optional<int> saved_after;  // the iteration of the last good state, once saved
  if (config.write_outputs)
    callbacks.on_failure = [&](const SimState& state) {
      write_checkpoint(checkpoint_file, Checkpoint{case_identity(config), nodes, state});
      saved_after = state.iterations_done;
    };
  // A failed run's message says where its last good state went and how to continue from it.
  const auto saved_note = [&] {
    return fmt::format("; the last good state (after iteration {}) is in {}: continue with --resume {}", *saved_after,
                       checkpoint_file.string(), config.out_dir.string());
  };
  SimResult result;
  // On a CPU device the pictures queued so far (the initial ones) wait for the simulation to end
  // (mesh_detail::kPictureHoldSeconds). run_core may have held them already, before it knew the device:
  // on any other device they are let go now.
  const bool cpu_device = backend.context && backend.context->device().type == "CPU";
  const PictureHold hold(phases, cpu_device, mesh_detail::kPictureHoldSeconds);
  if (!cpu_device) phases.hold_pictures(false);
  try {
    result = backend.simulator->run(nodes, inputs.node_tree(), spacing.field(), options, callbacks);
  } catch (const DeviceError& e) {
    if (!saved_after) throw;
    throw DeviceError(e.what() + saved_note() + " (with --device host if the device stays unusable)");
  } catch (const SimulationError& e) {
    if (!saved_after) throw;
    throw SimulationError(e.what() + saved_note());
  }
  hold.release();
  return result;
}

// The checkpoint after a run that writes outputs. Stopped by core/interrupt's flag: the nodes go to
// the checkpoint and nothing else is written (throws Interrupted). Stopped by the caller's flag:
// the checkpoint, and the outputs follow. Finished: a stale checkpoint is removed.
void keep_checkpoint(const CaseConfig& config, const NodeSet& nodes, const SimResult& result, const SimOptions& options,
                     const SimState* resume, const SimulateHooks* hooks) {
  const fs::path checkpoint_file = checkpoint_path(config.out_dir);
  if (interrupt_flag().load()) {
    // Ctrl-C (or --stop-after): triangulating and cleaning up an unsettled mesh would only delay the
    // stop. Stopped before an iteration of this run ended, there is nothing new to save (a resumed
    // run's checkpoint stays as it was).
    if (result.state.iterations_done == (resume ? resume->iterations_done : 0)) throw_interrupted();
    {
      const InterruptShield shield;
      write_checkpoint(checkpoint_file, Checkpoint{case_identity(config), nodes, result.state});
    }
    throw Interrupted(fmt::format("after iteration {} of {}{}; wrote {} and nothing else", result.state.iterations_done,
                                  options.iterations, result.converged ? " (converged)" : "",
                                  checkpoint_file.string()));
  }
  if (hooks && hooks->finished) *hooks->finished = result.state;
  if (result.stopped) {
    write_checkpoint(checkpoint_file, Checkpoint{case_identity(config), nodes, result.state});
    progress(config, "simulation: stopped after iteration {} of {}; wrote {} (continue with --resume {})",
             result.state.iterations_done, options.iterations, checkpoint_file.string(), config.out_dir.string());
  } else {
    // A checkpoint in DIR means the run there is unfinished; this one finished.
    std::error_code ec;
    fs::remove(checkpoint_file, ec);
  }
}

// The last progress lines: how the run ended, and its figures.
void report_result(const CaseConfig& config, const SimOptions& options, const SimResult& result, const SimState* resume,
                   std::size_t nodes) {
  if (result.converged) {
    progress(config, "simulation: converged after {} iterations (of at most {})", result.state.iterations_done,
             options.iterations);
  } else if (options.convergence.enabled && !result.stopped && result.state.iterations_done == options.iterations) {
    // A run that ran to its maximum says what held it (the rule's measurements are not printed otherwise).
    const int done = result.state.iterations_done;
    const bool settled =
        population_status(options.population, result.state.population, done, options.iterations).settled;
    const std::string why = ConvergenceMonitor(options.convergence, result.state.convergence)
                                .not_converged_reason(done, settled, result.state.population.last_change);
    if (why.empty())
      progress(config, "simulation: the stopping rule's conditions were met at the last iteration allowed, {}", done);
    else
      progress(config, "simulation: not converged in {} iterations: {}", done, why);
  }
  const SimStats& st = result.stats;
  const int iterations_run = result.state.iterations_done - (resume ? resume->iterations_done : 0);
  const double per_iteration = iterations_run > 0 ? st.seconds / iterations_run : 0.0;
  progress(config,
           "simulation: {:.2f} s ({:.3f} ms/iteration), initial dt_GM {:.4g}, {:.3g} pair interactions/s, "
           "{:.2f} pairs examined per pair within cutoff, {} nodes snapped",
           st.seconds, 1e3 * per_iteration, st.dt_initial,
           st.seconds > 0 ? static_cast<double>(st.pairs_within) / st.seconds : 0.0,
           st.pairs_within ? static_cast<double>(st.pairs_examined) / static_cast<double>(st.pairs_within) : 0.0,
           st.snapped);
  if (options.population.enabled)
    progress(config, "population control: {} events ({:.3f} s), {} nodes inserted, {} removed; {} nodes now",
             st.population_events, st.population_seconds, st.inserted, st.removed, nodes);
}

// DIR/history.csv, history.png and the final node outputs.
void write_outputs(const CaseConfig& config, const MeshInputs& inputs, const NodeSet& nodes, const SimResult& result,
                   RunPhases& phases) {
  const fs::path& dir = config.out_dir;
  {
    const auto csv_timer = phases.phase("history.csv");
    write_history_csv(dir / "history.csv", result.history);
  }
  if (config.output.wants("png")) {
    phases.picture("history.png", [path = dir / "history.png", rows = result.history,
                                   title = fmt::format("{} ({})", config.name, to_string(config.init.method))] {
      write_history_plot(path, rows, title);
    });
  }
  write_node_outputs(config, inputs, nodes, "final",
                     fmt::format("{} - final distribution ({}, {} iterations)", config.name,
                                 to_string(config.init.method), result.state.iterations_done),
                     nullptr, phases);
}

}  // namespace

SimResult simulate(const CaseConfig& config, const MeshInputs& inputs, const SpacingStage& spacing, NodeSet& nodes,
                   const SimState* resume, const SimulateHooks* hooks, RunPhases* run) {
  RunPhases local(false);
  RunPhases& phases = run ? *run : local;
  auto timer = phases.phase("simulation");
  // auto: the best OpenCL device whose program builds, else the host reference. An explicit opencl
  // spec that cannot be met throws InputError listing the devices (exit 2).
  const auto note = [&config](const std::string& line) { progress(config, "{}", line); };
  // A metric run: the host driver in metric mode (the device-resident loop has no metric mode), over
  // the host reference or an explicit device's step backend; population control measures in the metric.
  const MetricField* metric = spacing.metric();
  ChosenBackend own;
  const ChosenBackend& backend =
      metric ? (own = choose_metric_backend(config.simulation.device, config.simulation.precision, note))
      : hooks && hooks->backend ? hooks->backend(note)
                                : (own = choose_backend_for(config.simulation.device, config.simulation.precision,
                                                            static_cast<double>(nodes.size()), note));
  SimOptions options = simulation_options(config, nodes.size());
  options.metric = metric;
  options.stop = hooks && hooks->stop ? hooks->stop : &InterruptGuard::flag();
  options.resume = resume;
  // Smooth curves: the nodes live on the dense polyline, so the simulator builds its quadtree (leaves
  // tagged inside/boundary/outside) of the final field over that geometry instead. Otherwise the
  // spacing stage's quadtree: the final field itself, or (thesis) eq. 3.6's lookup table.
  options.background = inputs.dense ? nullptr : &spacing.background();
  announce(config, options, *backend.simulator, resume);
  SimResult result = run_on_backend(config, inputs, spacing, nodes, options, hooks, backend, phases);
  if (!config.write_outputs) return result;  // the Python API keeps the state in memory
  keep_checkpoint(config, nodes, result, options, resume, hooks);
  report_result(config, options, result, resume, nodes.size());
  timer.stop();
  phases.note("iterations", result.state.iterations_done);
  phases.note("converged", result.converged ? 1 : 0);
  phases.note("simulation_seconds", result.stats.seconds);
  // Where the iterations' time went: the stopping rule's measurements and the population events (the
  // host-serial parts), then the driver's own split.
  phases.note("measurements", result.stats.measurements);
  phases.note("measure_seconds", result.stats.measure_seconds);
  phases.note("measure_cpu_seconds", result.stats.measure_cpu_seconds);
  phases.note("measure_wait_seconds", result.stats.measure_wait_seconds);
  phases.note("population_events", result.stats.population_events);
  phases.note("population_seconds", result.stats.population_seconds);
  for (const auto& [name, seconds] : result.stats.split) phases.note(name, seconds);
  phases.note("backend", backend.simulator->describe());
  write_outputs(config, inputs, nodes, result, phases);
  return result;
}

}  // namespace pdmesh
