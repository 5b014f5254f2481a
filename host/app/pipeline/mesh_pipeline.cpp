// The `pdmesh mesh` pipeline: the simulation stage and run_mesh, which runs every stage in order
// (the inputs in mesh_inputs.cpp, the outputs in mesh_outputs.cpp).
#include "app/pipeline/mesh_pipeline.hpp"

#include <filesystem>
#include <future>
#include <optional>
#include <fmt/format.h>

#include "app/pipeline/exit_codes.hpp"
#include "app/pipeline/interrupt.hpp"
#include "app/pipeline/pipeline_detail.hpp"
#include "app/pipeline/output_guard.hpp"
#include "app/pipeline/resume.hpp"
#include "app/pipeline/stop_report.hpp"
#include "core/atomic_file.hpp"
#include "core/errors.hpp"
#include "core/interrupt.hpp"
#include "core/progress_notes.hpp"
#include "core/worker_pool.hpp"
#include "render/history_plot.hpp"

namespace pdmesh {

namespace fs = std::filesystem;
using mesh_detail::progress;
using mesh_detail::write_node_outputs;

SimOptions simulation_options(const CaseConfig& config) {
  SimOptions options;
  options.iterations = static_cast<int>(config.simulation.iterations);
  options.convergence.enabled = config.simulation.stop == StopRule::Converged;
  options.convergence.aspect_tolerance = config.simulation.stop_aspect;
  options.convergence.angle_tolerance = config.simulation.stop_angle;
  options.convergence.check_every = config.simulation.stop_every;
  options.convergence.window = config.simulation.stop_window;
  options.convergence.min_iterations = config.simulation.stop_min;
  options.dt_initial = config.simulation.dt_for(config.init.method);
  options.cutoff = config.simulation.cutoff;
  options.lj_a = config.simulation.lj_a;
  options.r0_any_direction = config.simulation.r0_any_direction;
  options.stability_factor = config.simulation.stability_factor;
  options.momentum = config.simulation.momentum;
  options.verlet_skin = default_verlet_skin(options.momentum);
  options.population = config.population;
  options.quiet = config.quiet;
  return options;
}

namespace {
// How long the initial pictures wait for a simulation on a CPU device (see simulate).
constexpr double kPictureHoldSeconds = 2.0;
}  // namespace

SimResult simulate(const CaseConfig& config, const MeshInputs& inputs, NodeSet& nodes, const SimState* resume,
                   const SimulateHooks* hooks, RunPhases* run) {
  RunPhases local(false);
  RunPhases& phases = run ? *run : local;
  auto timer = phases.phase("simulation");
  // auto: the best OpenCL device whose program builds, else the host reference. An explicit opencl
  // spec that cannot be met throws InputError listing the devices (exit 2).
  const auto note = [&config](const std::string& line) { progress(config, "{}", line); };
  const ChosenBackend backend =
      hooks && hooks->backend
          ? hooks->backend(note)
          : choose_backend_for(config.simulation.device, config.simulation.precision,
                               static_cast<double>(nodes.size()), note);
  SimOptions options = simulation_options(config);
  options.stop = hooks && hooks->stop ? hooks->stop : &InterruptGuard::flag();
  options.resume = resume;
  // The pipeline's quadtree: the final field itself, or (thesis) eq. 3.6's lookup table, built here.
  // (run_mesh builds it in its "spacing" phase, for the node estimate too.)
  const SpacingPipeline& pipeline = inputs.pipeline();
  // Smooth curves: the nodes live on the dense polyline, so the simulator builds its quadtree (leaves
  // tagged inside/boundary/outside) of the final field over that geometry instead.
  options.background = inputs.dense ? nullptr : &pipeline.background();
  progress(config, "simulation: {}{} iterations on {}, cutoff {}, a = {}, r0 rule {}, stability factor {}{}",
           options.convergence.enabled ? "until converged, at most " : "", options.iterations,
           backend.simulator->describe(), options.cutoff, options.lj_a,
           options.r0_any_direction ? "any_direction" : "force_direction", options.stability_factor,
           options.momentum > 0.0 ? fmt::format(", momentum {}", options.momentum) : std::string());
  if (resume) progress(config, "simulation: resuming after iteration {}", resume->iterations_done);
  const fs::path checkpoint_file = checkpoint_path(config.out_dir);
  SimCallbacks callbacks;
  if (config.stop_after > 0 || (hooks && hooks->on_iteration)) {
    callbacks.on_iteration = [&config, hooks](const HistoryRow& row) {
      if (config.stop_after > 0 && row.iteration == config.stop_after) InterruptGuard::flag().store(true);
      if (hooks && hooks->on_iteration) hooks->on_iteration(row);
    };
  }
  std::optional<int> saved_after;  // the iteration of the last good state, once saved
  if (config.write_outputs) callbacks.on_failure = [&](const SimState& state) {
    write_checkpoint(checkpoint_file, Checkpoint{case_identity(config), nodes, state});
    saved_after = state.iterations_done;
  };
  // A failed run's message says where its last good state went and how to continue from it.
  const auto saved_note = [&] {
    return fmt::format("; the last good state (after iteration {}) is in {}: continue with --resume {}", *saved_after,
                       checkpoint_file.string(), config.out_dir.string());
  };
  SimResult result;
  // On a CPU device the kernels keep every core busy, and a picture drawn beside them slows every
  // kernel (each waits for its slowest thread): the pictures queued so far (the initial ones) wait
  // for the simulation to end, and are drawn beside the serial work after it (the cleanup); for 2 s
  // at most, so that a long run still shows its initial pictures early.
  const PictureHold hold(phases, backend.context && backend.context->device().type == "CPU", kPictureHoldSeconds);
  try {
    result = backend.simulator->run(nodes, inputs.node_tree(), inputs.field(), options, callbacks);
  } catch (const DeviceError& e) {
    if (!saved_after) throw;
    throw DeviceError(e.what() + saved_note() + " (with --device host if the device stays unusable)");
  } catch (const SimulationError& e) {
    if (!saved_after) throw;
    throw SimulationError(e.what() + saved_note());
  }
  hold.release();
  if (!config.write_outputs) return result;  // the Python API keeps the state in memory
  if (interrupt_flag().load()) {
    // Ctrl-C (or --stop-after): the nodes as they are go to the checkpoint, and nothing else is
    // written: triangulating and cleaning up an unsettled mesh would only delay the stop. Stopped
    // before an iteration of this run ended, there is nothing new to save (a resumed run's
    // checkpoint stays as it was).
    if (result.state.iterations_done == (resume ? resume->iterations_done : 0)) throw_interrupted();
    {
      const InterruptShield shield;
      write_checkpoint(checkpoint_file, Checkpoint{case_identity(config), nodes, result.state});
    }
    throw Interrupted(fmt::format("after iteration {} of {}{}; wrote {} and nothing else",
                                  result.state.iterations_done, options.iterations,
                                  result.converged ? " (converged)" : "", checkpoint_file.string()));
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
  if (result.converged) {
    progress(config, "simulation: converged after {} iterations (of at most {})", result.state.iterations_done,
             options.iterations);
  } else if (options.convergence.enabled && !result.stopped && result.state.iterations_done == options.iterations) {
    // A run that ran to its maximum says what held it (the rule's measurements are not printed otherwise).
    const int done = result.state.iterations_done;
    const bool settled =
        population_status(options.population, result.state.population, done, options.iterations).settled;
    const std::string why =
        ConvergenceMonitor(options.convergence, result.state.convergence).not_converged_reason(done, settled);
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
             st.population_events, st.population_seconds, st.inserted, st.removed, nodes.size());
  timer.stop();
  phases.note("iterations", result.state.iterations_done);
  phases.note("converged", result.converged ? 1 : 0);
  phases.note("simulation_seconds", st.seconds);
  phases.note("backend", backend.simulator->describe());
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
  return result;
}

namespace {

// One line on what the spacing pipeline built (nothing in the thesis' case: eq. 3.6 is used exactly).
void report_spacing(const CaseConfig& config, const MeshInputs& inputs) {
  const SpacingPipeline& p = inputs.pipeline();
  const SpacingOptions& o = p.options();
  const SpacingStats& s = p.stats();
  const BackgroundStats& b = p.background().stats();
  if (p.exact()) {
    progress(config,
             "spacing field: eq. 3.6 (thesis), evaluated exactly; its quadtree ({} leaves from {} evaluations of "
             "eq. 3.6, {:.3f} s) for the node estimate and the simulation",
             b.leaves, b.exact_evaluations, s.base_seconds);
    return;
  }
  progress(config,
           "spacing field: {:.3f} s (base {:.3f} s, sources {:.3f} s, gradation {:.3f} s, refinement {:.3f} s in {} "
           "rounds); scale {}, gradation {}, rows in gap {}, curvature angle {} deg; {} leaves ({} before the limits), "
           "q lowered at {} of {} corners",
           s.seconds, s.base_seconds, s.source_seconds, s.limit_seconds, s.refine_seconds, s.rounds, o.scale, o.gradation,
           o.rows_in_gap, o.curvature_angle, b.leaves, s.base_leaves, s.reduced_corners, b.corners);
}

// Runs `stages` (the simulation and what follows it). A stop request after the simulation has ended
// (`finished` set by SimulateHooks::finished) writes its nodes to the checkpoint, which a stop in
// the simulation has written itself (and named in its message), and throws on saying so.
template <class Stages>
void checkpoint_on_stop(const CaseConfig& config, const NodeSet& nodes, const std::optional<SimState>& finished,
                        const Stages& stages) {
  try {
    stages();
  } catch (const Interrupted& e) {
    if (std::string(e.what()) != "interrupted" || !finished || !config.write_outputs) throw;
    const fs::path file = checkpoint_path(config.out_dir);
    {
      const InterruptShield shield;
      write_checkpoint(file, Checkpoint{case_identity(config), nodes, *finished});
    }
    throw Interrupted(fmt::format("after the simulation had ended (iteration {}); wrote its nodes to {} (the files "
                                  "written whole before the stop stay)",
                                  finished->iterations_done, file.string()));
  }
}

// `--resume`: the node set and driver state come from the checkpoint instead of the initialization
// (whose outputs the interrupted run already wrote). With --iterations 0 the checkpoint's nodes are
// meshed as they are, and the checkpoint stays (the run can still be continued).
void resume_mesh(const CaseConfig& config, const MeshInputs& inputs, RunPhases& phases) {
  auto timer = phases.phase("checkpoint");
  const bool mesh_as_is = config.simulation.iterations == 0;
  Checkpoint checkpoint = read_checkpoint_for(*config.resume, config, inputs.node_tree());
  timer.stop();
  {
    const auto spacing_timer = phases.phase("spacing");
    (void)inputs.background();
  }
  {
    const auto estimate_timer = phases.phase("estimate");
    check_node_limit(config, inputs);
  }
  report_spacing(config, inputs);
  prepare_output_directory(config);
  NodeSet nodes = std::move(checkpoint.nodes);
  if (mesh_as_is) {
    progress(config, "mesh: the nodes of the checkpoint as they are, after iteration {} (the checkpoint stays)",
             checkpoint.state.iterations_done);
    mesh_and_measure(config, inputs, nodes, &phases);
    return;
  }
  const PictureGuard guard(phases);
  std::optional<SimState> finished;
  SimulateHooks hooks;
  hooks.finished = &finished;
  checkpoint_on_stop(config, nodes, finished, [&] {
    const SimResult result = simulate(config, inputs, nodes, &checkpoint.state, &hooks, &phases);
    mesh_and_measure(config, inputs, nodes, &phases, result.final_mesh.get());
    check_interrupt();  // a stop while the last pictures were abandoned
  });
}

// choose_backend's result, its notes and its error, for a run that sets the backend up on a thread.
struct PreparedBackend {
  ChosenBackend backend;
  std::vector<std::string> notes;
  std::exception_ptr error;
};

PreparedBackend prepare_backend(const CaseConfig& config) {
  PreparedBackend p;
  try {
    p.backend = choose_backend(config.simulation.device, config.simulation.precision,
                               [&p](const std::string& line) { p.notes.push_back(line); });
  } catch (...) {
    p.error = std::current_exception();
  }
  return p;
}

// The summary line, and the JSON when --timings asks for it.
void report_phases(const CaseConfig& config, const RunPhases& phases) {
  progress(config, "{}", phases.summary());
  if (config.timings_file) write_file_atomically(*config.timings_file, phases.json());
}

}  // namespace

namespace {

// Every stage in order (run_mesh without the stop handling).
void run_stages(const CaseConfig& config, RunPhases& phases) {
  // Stage 1: inputs.
  auto timer = phases.phase("read");
  const MeshInputs inputs(config);
  check_interrupt();  // a stop while reading is acted on here at the latest
  timer.stop();
  progress(config, "geometry: {} curves, {} segments, {} loops, area {:.6g}", inputs.geometry.curves.size(),
           inputs.geometry.segments.size(), inputs.geometry.loops.size(), inputs.geometry.area);
  if (!inputs.spacing_summary.empty()) progress(config, "{}", inputs.spacing_summary);
  if (inputs.dense)
    progress(config, "geometry: smooth curves (centripetal Catmull-Rom) as a dense polyline of {} segments, area {:.6g}",
             inputs.dense->geometry.segments.size(), inputs.dense->geometry.area);
  if (!inputs.smooth_fallback.empty())
    progress(config, "note: geometry.curves = \"smooth\" fell back to the input polylines: {}", inputs.smooth_fallback);
  // An explicit OpenCL device that is not there is bad input: refuse it before anything is written.
  if (config.simulation.iterations > 0 && config.simulation.device != "host" && config.simulation.device != "auto")
    (void)ocl::select_device(config.simulation.device);
  // parallel_for's helpers before any backend starts: creating a thread waits while the backend's
  // dlopen runs (core/worker_pool.hpp), and the spacing phase's parallel loops would wait for it.
  start_workers();
  if (config.resume) {
    resume_mesh(config, inputs, phases);
    return;
  }
  // The simulation's backend (OpenCL platforms, context, program from PoCL's cache: ~0.05 s wall on
  // 30P30N) is set up on a thread while this one builds the spacing field, estimates and fills, which
  // leave a core idle part of the time. Its notes and errors come out when the simulation starts.
  std::future<PreparedBackend> prepared;
  if (config.simulation.iterations > 0 && config.simulation.device != "host")
    prepared = std::async(std::launch::async, [&config] { return prepare_backend(config); });
  // Stage 2: the final spacing field (the pipeline), then the limits, before any large allocation.
  // The quadtree of the final field (in the thesis preset eq. 3.6's lookup table, which the node
  // estimate and the simulation read) is built here.
  timer = phases.phase("spacing");
  (void)inputs.background();
  timer.stop();
  report_spacing(config, inputs);
  timer = phases.phase("estimate");
  const double estimate = check_node_limit(config, inputs);
  timer.stop();
  // `--device auto` on a small case takes the host reference: the backend set up beside the spacing
  // phase is then left unused (the run waits for its thread only at its end).
  const bool use_prepared = !auto_prefers_host(config.simulation.device, estimate);
  // Stage 3: initial distribution (the boundary placement, then the fill).
  timer = phases.phase("fill");
  const InitialDistribution initial = make_initial(config, inputs);
  timer.stop();
  progress(config, "initial distribution: {} nodes (estimate {:.0f} by hexagonal packing; {} fixed, {} boundary, "
           "{} interior of which {} by overloading)",
           initial.nodes.size(), estimate, initial.nodes.count(NodeKind::Fixed),
           initial.nodes.count(NodeKind::Boundary), initial.nodes.count(NodeKind::Interior), initial.overload_nodes);
  phases.note("estimate", estimate);
  phases.note("initial_nodes", static_cast<double>(initial.nodes.size()));
  // Stage 4: outputs. Later stages (simulation, triangulation, mesh files) follow the same pattern:
  // compute, then write atomically into the directory prepared here.
  prepare_output_directory(config);
  if (config.output.spacing_picture) {
    const auto spacing_picture_timer = phases.phase("spacing.png");
    write_spacing_picture(config, inputs);
  }
  NodeSet nodes = initial.nodes;
  // The initial pictures read `initial` while the simulation moves `nodes`.
  const PictureGuard guard(phases);
  write_initial_outputs(config, inputs, initial, &phases);
  // Stage 5: the simulation (none with --iterations 0: the initial distribution is meshed).
  std::optional<SimState> finished;
  checkpoint_on_stop(config, nodes, finished, [&] {
    std::shared_ptr<const Mesh> final_mesh;
    if (config.simulation.iterations > 0) {
      SimulateHooks hooks;
      if (prepared.valid() && use_prepared) {
        hooks.backend = [&prepared](const std::function<void(const std::string&)>& note) {
          PreparedBackend p = prepared.get();
          for (const std::string& line : p.notes) note(line);
          if (p.error) std::rethrow_exception(p.error);
          return std::move(p.backend);
        };
      }
      hooks.finished = &finished;
      final_mesh = simulate(config, inputs, nodes, nullptr, &hooks, &phases).final_mesh;
    }
    // Stage 6: the mesh, its quality and its files (a converged run has triangulated its final nodes).
    mesh_and_measure(config, inputs, nodes, &phases, final_mesh.get());
    check_interrupt();  // a stop while the last pictures were abandoned
  });
}

}  // namespace

int run_mesh(const CaseConfig& config) {
  // The long phases' progress notes (core/progress_notes.hpp) go where the progress lines go.
  // A phase that runs long with nothing to say gets a "still running" line from the heartbeat.
  struct Notes {
    explicit Notes(bool quiet) {
      if (quiet) return;
      set_progress_sink([](const std::string& line) { fmt::print(stderr, "{}\n", line); });
      heartbeat = std::make_unique<ProgressHeartbeat>();
    }
    ~Notes() {
      heartbeat.reset();
      set_progress_sink({});
    }
    std::unique_ptr<ProgressHeartbeat> heartbeat;
  } notes(config.quiet);
  RunPhases phases;
  // SIGINT/SIGTERM from here on stop the run wherever it is (exit 130, app/pipeline/stop_report).
  InterruptGuard interrupt;
  // Before any work: no output replaces an input, every output is writable, and --out is this run's
  // alone (app/pipeline/output_guard).
  check_outputs(config);
  try {
    run_stages(config, phases);
  } catch (const Interrupted& e) {
    const std::string what = e.what();
    report_stop(config, phases.current_phase(), InterruptGuard::signal_number(),
                what == "interrupted" ? std::nullopt : std::optional<std::string>(what));
    return kExitInterrupted;
  }
  report_phases(config, phases);
  return InterruptGuard::flag().load() ? kExitInterrupted : kExitOk;
}

}  // namespace pdmesh
