// The `pdmesh mesh` pipeline: run_mesh, which runs every stage in order (mesh_pipeline.hpp lists them;
// stages read, spacing and initial in mesh_inputs.cpp, simulation in simulate_stage.cpp, the outputs
// and stage mesh in mesh_outputs.cpp).
#include "app/pipeline/mesh_pipeline.hpp"

#include <filesystem>
#include <future>
#include <optional>
#include <fmt/format.h>

#include "app/pipeline/exit_codes.hpp"
#include "app/pipeline/interrupt.hpp"
#include "app/pipeline/mesh_handover.hpp"
#include "app/pipeline/layer_pipeline.hpp"
#include "app/pipeline/periodic_pipeline.hpp"
#include "app/pipeline/pipeline_detail.hpp"
#include "app/pipeline/output_guard.hpp"
#include "app/pipeline/resume.hpp"
#include "app/pipeline/stop_report.hpp"
#include "core/atomic_file.hpp"
#include "core/errors.hpp"
#include "core/interrupt.hpp"
#include "core/progress_notes.hpp"
#include "core/worker_pool.hpp"
#include "geometry/heal_report.hpp"

namespace pdmesh {

namespace fs = std::filesystem;
using mesh_detail::progress;

namespace {

// One line on what the spacing pipeline built (nothing in the thesis' case: eq. 3.6 is used exactly).
void report_spacing(const CaseConfig& config, const SpacingStage& spacing) {
  const SpacingPipeline& p = spacing.pipeline();
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
           s.seconds, s.base_seconds, s.source_seconds, s.limit_seconds, s.refine_seconds, s.rounds, o.scale,
           o.gradation, o.rows_in_gap, o.curvature_angle, b.leaves, s.base_leaves, s.reduced_corners, b.corners);
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
    throw Interrupted(
        fmt::format("after the simulation had ended (iteration {}); wrote its nodes to {} (the files "
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
  timer = phases.phase("spacing");
  const SpacingStage spacing(config, inputs);
  timer.stop();
  {
    const auto estimate_timer = phases.phase("estimate");
    check_node_limit(config, inputs, spacing);
  }
  report_spacing(config, spacing);
  prepare_output_directory(config);
  NodeSet nodes = std::move(checkpoint.nodes);
  if (mesh_as_is) {
    progress(config, "mesh: the nodes of the checkpoint as they are, after iteration {} (the checkpoint stays)",
             checkpoint.state.iterations_done);
    mesh_and_measure(config, inputs, spacing, nodes, &phases);
    return;
  }
  const PictureGuard guard(phases);
  std::optional<SimState> finished;
  SimulateHooks hooks;
  hooks.finished = &finished;
  checkpoint_on_stop(config, nodes, finished, [&] {
    const SimResult result = simulate(config, inputs, spacing, nodes, &checkpoint.state, &hooks, &phases);
    mesh_and_measure(config, inputs, spacing, nodes, &phases, result.final_mesh.get());
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

// Stage read, with its progress lines.
void read_stage_report(const CaseConfig& config, const MeshInputs& inputs) {
  progress(config, "geometry: {} curves, {} segments, {} loops, area {:.6g}", inputs.geometry.curves.size(),
           inputs.geometry.segments.size(), inputs.geometry.loops.size(), inputs.geometry.area);
  for (const std::string& line : heal_report_lines(inputs.healing)) progress(config, "{}", line);
  if (!inputs.spacing_summary.empty()) progress(config, "{}", inputs.spacing_summary);
  if (config.geometry_alone && !config.farfield.given() && inputs.geometry.loops.size() == 1)
    progress(config,
             "note: the geometry is one closed loop: its inside is meshed; to mesh the domain around it, add "
             "a far field, e.g. --farfield circle:20 (docs/geometry-input.md, \"Far field\")");
  if (inputs.dense)
    progress(config,
             "geometry: smooth curves (centripetal Catmull-Rom) as a dense polyline of {} segments, area {:.6g}",
             inputs.dense->geometry.segments.size(), inputs.dense->geometry.area);
  if (!inputs.smooth_fallback.empty())
    progress(config, "note: geometry.curves = \"smooth\" fell back to the input polylines: {}", inputs.smooth_fallback);
}

// The stages simulation and mesh of a new run, from the initial nodes on (moved in place).
// With [[boundary_layer]]: the case and inputs of the whole domain, the layers, and the core's inputs (which
// `config` and `inputs` of simulate_and_mesh then are).
struct LayeredRun {
  const CaseConfig& config;
  const MeshInputs& inputs;
  const LayeredCase& layered;
};

void simulate_and_mesh(const CaseConfig& config, const MeshInputs& inputs, const SpacingStage& spacing, NodeSet& nodes,
                       std::future<PreparedBackend>& prepared, bool use_prepared, RunPhases& phases,
                       const LayeredRun* layered = nullptr) {
  std::optional<SimState> finished;
  checkpoint_on_stop(config, nodes, finished, [&] {
    std::shared_ptr<const Mesh> final_mesh;
    if (config.simulation.iterations > 0) {
      SimulateHooks hooks;
      std::optional<ChosenBackend> backend;  // the prepared one, for this simulation
      if (prepared.valid() && use_prepared) {
        hooks.backend = [&prepared, &backend](const std::function<void(const std::string&)>& note) -> ChosenBackend& {
          PreparedBackend p = prepared.get();
          for (const std::string& line : p.notes) note(line);
          if (p.error) std::rethrow_exception(p.error);
          return backend.emplace(std::move(p.backend));
        };
      }
      // The node count that decides `--device auto` can differ from the estimate that set use_prepared:
      // simulate may then set up an OpenCL backend itself, and PoCL's first platform queries are not
      // safe beside the preparing thread's (a crash in clGetPlatformInfo): that thread ends first.
      if (prepared.valid() && !use_prepared) prepared.wait();
      hooks.finished = &finished;
      final_mesh = simulate(config, inputs, spacing, nodes, nullptr, &hooks, &phases).final_mesh;
    }
    // A converged run has triangulated its final nodes.
    if (layered) {
      // The core's cleaned mesh, written with the layer cells.
      const Mesh mesh = mesh_layered_core(config, inputs, spacing, nodes, layered->layered, &phases, final_mesh.get());
      write_layered_outputs(layered->config, layered->inputs, layered->layered, inputs, mesh, phases);
    } else {
      mesh_and_measure(config, inputs, spacing, nodes, &phases, std::move(final_mesh));
    }
    check_interrupt();  // a stop while the last pictures were abandoned
  });
}

void run_core(const CaseConfig& config, const MeshInputs& inputs, const SpacingStage& spacing,
              std::future<PreparedBackend>& prepared, RunPhases& phases, const LayeredRun* layered);

// Every stage in order (run_mesh without the stop handling).
void run_stages(const CaseConfig& config, RunPhases& phases) {
  auto timer = phases.phase("read");
  const MeshInputs inputs(config);
  check_interrupt();  // a stop while reading is acted on here at the latest
  timer.stop();
  check_periodic(config, inputs);  // a bad [[periodic]] table is said before anything else
  read_stage_report(config, inputs);
  // An explicit OpenCL device that is not there is bad input: refuse it before anything is written.
  if (config.simulation.iterations > 0 && config.simulation.device != "host" && config.simulation.device != "auto")
    (void)ocl::select_device(config.simulation.device);
  // parallel_for's helpers before any backend starts: creating a thread waits while the backend's
  // dlopen runs (core/worker_pool.hpp), and the spacing phase's parallel loops would wait for it.
  start_workers();
  if (config.resume && !config.boundary_layers.empty())
    throw InputError(fmt::format("{}: --resume is not supported with [[boundary_layer]]", config.source.string()));
  if (config.resume) {
    resume_mesh(config, inputs, phases);
    return;
  }
  // The simulation's backend (OpenCL platforms, context, program from PoCL's cache: ~0.05 s wall on
  // 30P30N) is set up on a thread while this one builds the spacing field, estimates and fills, which
  // leave a core idle part of the time. Its notes and errors come out when the simulation starts.
  std::future<PreparedBackend> prepared;
  // A metric run takes its backend in simulate (choose_metric_backend): nothing to prepare.
  if (config.simulation.iterations > 0 && config.simulation.device != "host" && !config.spacing.metric())
    prepared = std::async(std::launch::async, [&config] { return prepare_backend(config); });
  // The final spacing field and its quadtree (in the thesis preset eq. 3.6's lookup table, which the
  // node estimate and the simulation read), then the limits, before any large allocation.
  timer = phases.phase("spacing");
  const SpacingStage case_spacing(config, inputs);
  timer.stop();
  report_spacing(config, case_spacing);
  // With [[boundary_layer]] the later stages mesh the core: the case on the layer fronts.
  std::unique_ptr<LayeredCase> layered;
  std::unique_ptr<MeshInputs> core_inputs;
  std::unique_ptr<SpacingStage> core_spacing;
  if (!config.boundary_layers.empty()) {
    timer = phases.phase("layers");
    layered = build_layers(config, inputs, case_spacing);
    timer.stop();
    timer = phases.phase("core spacing");
    core_inputs = layered_core_inputs(*layered, inputs);
    core_inputs->projection = inputs.projection;
    core_spacing = std::make_unique<SpacingStage>(layered->core, *core_inputs);
    timer.stop();
  }
  if (!config.periodic.empty()) {
    // With [[periodic]] the later stages mesh the case (with layers: the core's case) on the periodic
    // nodes, fixed; the layers' end columns on the periodic curves are paired already.
    const CaseConfig& on = layered ? layered->core : config;
    const MeshInputs& on_inputs = layered ? *core_inputs : inputs;
    timer = phases.phase("periodic");
    const std::unique_ptr<PeriodicCase> periodic =
        build_periodic(on, on_inputs, layered ? *core_spacing : case_spacing);
    for (const std::string& line : periodic->notes) progress(config, "{}", line);
    const std::unique_ptr<MeshInputs> periodic_inputs = periodic_core_inputs(*periodic, on_inputs);
    const SpacingStage periodic_spacing(periodic->core, *periodic_inputs);
    timer.stop();
    if (!layered) {
      run_core(periodic->core, *periodic_inputs, periodic_spacing, prepared, phases, nullptr);
      return;
    }
    const LayeredRun layered_run{config, inputs, *layered};
    run_core(periodic->core, *periodic_inputs, periodic_spacing, prepared, phases, &layered_run);
    return;
  }
  if (!layered) {
    run_core(config, inputs, case_spacing, prepared, phases, nullptr);
    return;
  }
  const LayeredRun layered_run{config, inputs, *layered};
  run_core(layered->core, *core_inputs, *core_spacing, prepared, phases, &layered_run);
}

// The stages from the node estimate on, for the case (or, with layers, for the core).
void run_core(const CaseConfig& config, const MeshInputs& inputs, const SpacingStage& spacing,
              std::future<PreparedBackend>& prepared, RunPhases& phases, const LayeredRun* layered) {
  auto timer = phases.phase("estimate");
  const double estimate = check_node_limit(config, inputs, spacing);
  timer.stop();
  // `--device auto` on a small case takes the host reference: the backend set up beside the spacing
  // phase is then left unused (the run waits for its thread only at its end).
  const bool use_prepared = !auto_prefers_host(config.simulation.device, estimate);
  timer = phases.phase("fill");
  auto initial = std::make_shared<const InitialDistribution>(make_initial(config, inputs, spacing));
  timer.stop();
  progress(config,
           "initial distribution: {} nodes (estimate {:.0f} by hexagonal packing; {} fixed, {} boundary, "
           "{} interior of which {} by overloading)",
           initial->nodes.size(), estimate, initial->nodes.count(NodeKind::Fixed),
           initial->nodes.count(NodeKind::Boundary), initial->nodes.count(NodeKind::Interior), initial->overload_nodes);
  phases.note("estimate", estimate);
  phases.note("initial_nodes", static_cast<double>(initial->nodes.size()));
  // The outputs: every later stage computes, then writes atomically into the directory prepared here.
  prepare_output_directory(config);
  if (config.output.spacing_picture) {
    const auto spacing_picture_timer = phases.phase("spacing.png");
    write_spacing_picture(config, inputs, spacing);
  }
  NodeSet nodes = initial->nodes;
  // The initial pictures hold `initial` while the simulation moves `nodes`; it is freed once they are
  // drawn (on a CPU device after the simulation, or 2 s into it), not kept to the end of the run. The
  // guard: the final pictures read `nodes`.
  const PictureGuard guard(phases);
  // A simulation on the backend prepared beside the spacing phase may run on a CPU device, whose
  // kernels a picture drawn beside them would slow (mesh_detail::kPictureHoldSeconds): the initial
  // pictures are held from the start, not only once the simulation has begun (by then the background
  // thread would be drawing them); the simulation lets them go if the device is not a CPU.
  const PictureHold hold(phases, config.simulation.iterations > 0 && prepared.valid() && use_prepared,
                         mesh_detail::kPictureHoldSeconds);
  write_initial_outputs(config, inputs, initial, phases);
  initial.reset();
  // None with --iterations 0: the initial distribution is meshed.
  simulate_and_mesh(config, inputs, spacing, nodes, prepared, use_prepared, phases, layered);
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
