// The `pdmesh mesh` pipeline: read and check inputs, check limits, initialize, write outputs.
#include "app/mesh_command.hpp"

#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <optional>
#include <fmt/format.h>

#include "app/exit_codes.hpp"
#include "app/interrupt.hpp"
#include "app/resume.hpp"
#include "core/atomic_file.hpp"
#include "core/errors.hpp"
#include "geometry/geometry_files.hpp"
#include "io/mesh_formats.hpp"
#include "mesh/mesh_check.hpp"
#include "mesh/quality.hpp"
#include "mesh/quality_report.hpp"
#include "mesh/triangulate_nodes.hpp"
#include "nodes/node_domain.hpp"
#include "nodes/node_file.hpp"
#include "opencl/context.hpp"
#include "opencl/devices.hpp"
#include "render/history_plot.hpp"
#include "render/mesh_picture.hpp"
#include "render/node_picture.hpp"
#include "sim/history.hpp"
#include "spacing/resolution_check.hpp"

namespace pdmesh {

namespace fs = std::filesystem;

namespace {

// Every node is an element in an SVG; beyond this many the file would run to hundreds of
// megabytes, so only the PNG pictures (and zoomed views) are written.
constexpr std::size_t kSvgNodeLimit = 500'000;

const char* method_name(InitMethod m) { return m == InitMethod::Structured ? "structured" : "random"; }

template <class... Args>
void progress(const CaseConfig& config, fmt::format_string<Args...> format, Args&&... args) {
  if (!config.quiet) fmt::print(stderr, "{}\n", fmt::format(format, std::forward<Args>(args)...));
}

}  // namespace

MeshInputs::MeshInputs(const CaseConfig& config) {
  std::vector<std::string> files;
  for (const fs::path& f : config.geometry.files) files.push_back(f.string());
  GeometryOptions options;
  options.join_tolerance = config.geometry.join_tolerance;
  options.corner_angle_deg = config.geometry.corner_angle;
  geometry = read_geometry(files, config.geometry.curve_names, options);
  // Curve names are fields in node and mesh files; one with white space would break them later.
  for (std::size_t c = 0; c < geometry.curves.size(); ++c) {
    const std::string& name = geometry.curves[c].name;
    if (name.empty() || name.find_first_of(" \t\r\n") != std::string::npos) {
      throw InputError(fmt::format("{}:{}: curve {} name '{}' is empty or contains white space; name the curves "
                                   "with geometry.curve_names",
                                   geometry.curves[c].file, geometry.curves[c].line, c, name));
    }
  }
  tree = std::make_unique<GeometryTree>(geometry);
  if (config.spacing.field == SpacingKind::Expression) {
    spacing = std::make_unique<ExpressionSpacing>(config.spacing.expression);
  } else {
    spacing = std::make_unique<BoundarySpacing>(*tree);
  }
  // Before anything else uses them: with unresolvable coordinates the node estimate's tree could
  // refine without end.
  check_coordinate_resolution(geometry, *spacing);
}

std::vector<std::string> MeshInputs::curve_names() const {
  std::vector<std::string> names;
  for (const Curve& c : geometry.curves) names.push_back(c.name);
  return names;
}

double check_node_limit(const CaseConfig& config, const MeshInputs& inputs) {
  const double estimate = estimate_node_count(*inputs.tree, *inputs.spacing);
  const auto limit = static_cast<double>(config.max_nodes);
  if (!std::isfinite(estimate) || estimate > limit) {
    throw LimitError(fmt::format("{}: the spacing field asks for about {:.0f} nodes (hexagonal-packing estimate), "
                                 "more than --max-nodes {}; coarsen the spacing or raise --max-nodes",
                                 config.source.string(), estimate, config.max_nodes));
  }
  if (config.init.total > config.max_nodes) {
    throw LimitError(fmt::format("{}: init.total = {} is more than --max-nodes {}", config.source.string(),
                                 config.init.total, config.max_nodes));
  }
  return estimate;
}

InitialDistribution make_initial(const CaseConfig& config, const MeshInputs& inputs) {
  InitOptions options;
  options.method = config.init.method;
  options.seed = config.init.seed;
  if (config.init.total > 0) options.total = static_cast<std::size_t>(config.init.total);
  options.with_estimate = false;  // check_node_limit computed it just before
  return make_initial_distribution(*inputs.tree, *inputs.spacing, options);
}

void prepare_output_directory(const CaseConfig& config) {
  std::error_code ec;
  fs::create_directories(config.out_dir, ec);
  if (ec || !fs::is_directory(config.out_dir)) {
    throw InputError(fmt::format("cannot create output directory '{}': {}", config.out_dir.string(),
                                 ec ? ec.message() : std::string("a file of that name exists")));
  }
  // A run killed while writing leaves its temporary beside the file it was writing.
  const std::size_t stale = remove_stale_temporaries(config.out_dir);
  if (stale > 0)
    progress(config, "removed {} temporary file(s) left in {} by a run that was killed while writing", stale,
             config.out_dir.string());
}

namespace {

// STAGE.nodes, and (as output.formats asks) STAGE.png and STAGE_<view>.png, STAGE.svg, for one node
// distribution. The pictures go to `run`'s background thread: `nodes` (and the tree quads) must stay
// unchanged until run.wait_pictures().
void write_node_outputs(const CaseConfig& config, const MeshInputs& inputs, const NodeSet& nodes,
                        const std::string& stage, const std::string& title, const std::vector<Box>* tree_quads,
                        RunPhases& run) {
  const fs::path& dir = config.out_dir;
  {
    const auto timer = run.phase(stage + ".nodes");
    write_node_file(dir / (stage + ".nodes"), nodes, inputs.curve_names());
  }
  NodePictureOptions picture;
  picture.title = title;
  picture.tree_quads = tree_quads;
  const Geometry* geometry = &inputs.geometry;
  const NodeSet* drawn = &nodes;
  std::vector<std::string> names;
  const auto draw = [&](const std::string& file, const NodePictureOptions& options) {
    run.picture(file, [geometry, drawn, options, path = dir / file] { write_node_picture(path, *geometry, *drawn, options); });
    names.push_back(file);
  };
  if (config.output.wants("png")) {
    draw(stage + ".png", picture);
    for (const ViewWindow& view : config.output.views) {
      NodePictureOptions zoomed = picture;
      zoomed.title += " - " + view.name;
      zoomed.window = view.window;
      draw(fmt::format("{}_{}.png", stage, view.name), zoomed);
    }
  }
  if (config.output.wants("svg")) {
    if (nodes.size() <= kSvgNodeLimit) {
      draw(stage + ".svg", picture);
    } else {
      progress(config, "{}.svg skipped: {} nodes is more than {} (the PNG pictures are written)", stage, nodes.size(),
               kSvgNodeLimit);
    }
  }
  progress(config, "wrote {}/{}.nodes{}", dir.string(), stage,
           names.empty() ? "" : fmt::format("; drawing {}", fmt::join(names, ", ")));
}

}  // namespace

void write_initial_outputs(const CaseConfig& config, const MeshInputs& inputs, const InitialDistribution& initial,
                           RunPhases* run) {
  RunPhases local(false);
  write_node_outputs(config, inputs, initial.nodes, "initial",
                     fmt::format("{} - initial distribution ({})", config.name, method_name(config.init.method)),
                     config.output.tree_overlay ? &initial.tree_quads : nullptr, run ? *run : local);
}

SimOptions simulation_options(const CaseConfig& config) {
  SimOptions options;
  options.iterations = static_cast<int>(config.simulation.iterations);
  options.convergence.enabled = config.simulation.stop == StopRule::Converged;
  options.dt_initial = config.simulation.dt_for(config.init.method);
  options.cutoff = config.simulation.cutoff;
  options.lj_a = config.simulation.lj_a;
  options.r0_any_direction = config.simulation.r0_any_direction;
  options.stability_factor = config.simulation.stability_factor;
  options.quiet = config.quiet;
  return options;
}

SimResult simulate(const CaseConfig& config, const MeshInputs& inputs, NodeSet& nodes, const SimState* resume,
                   RunPhases* run) {
  RunPhases local(false);
  RunPhases& phases = run ? *run : local;
  auto timer = phases.phase("simulation");
  const std::string& device = config.simulation.device;
  // auto: the first GPU, else the first CPU OpenCL device, else the host reference. An explicit
  // opencl spec that cannot be met throws InputError listing the devices (exit 2).
  std::optional<ocl::DeviceInfo> chosen;
  if (device != "host") {
    chosen = ocl::select_device(device);
    if (!chosen) progress(config, "note: no OpenCL platform or device found; simulating on the host reference");
  }
  bool use_float = config.simulation.precision == Precision::Float;
  if (!chosen && use_float)
    progress(config, "note: the host reference computes in double precision; --precision float is ignored");
  if (chosen && !use_float && !chosen->fp64) {
    progress(config, "note: {} has no double precision (cl_khr_fp64); simulating in float", chosen->name);
    use_float = true;
  }
  std::unique_ptr<ocl::Context> context;
  if (chosen) context = std::make_unique<ocl::Context>(*chosen);
  SimOptions options = simulation_options(config);
  options.device = context.get();
  options.device_float = use_float;
  options.stop = &InterruptGuard::flag();
  options.resume = resume;
  const std::string where = chosen ? fmt::format("opencl:{}:{} ({}, {}, {}, device-resident)", chosen->platform,
                                                 chosen->device, chosen->name, chosen->type,
                                                 use_float ? "float" : "double")
                                   : std::string("the host reference (double)");
  progress(config, "simulation: {}{} iterations on {}, cutoff {}, a = {}, r0 rule {}, stability factor {}",
           options.convergence.enabled ? "until converged, at most " : "", options.iterations, where, options.cutoff, options.lj_a,
           options.r0_any_direction ? "any_direction" : "force_direction", options.stability_factor);
  if (resume) progress(config, "simulation: resuming after iteration {}", resume->iterations_done);
  const fs::path checkpoint_file = checkpoint_path(config.out_dir);
  SimCallbacks callbacks;
  if (config.stop_after > 0) {
    callbacks.on_iteration = [&config](const HistoryRow& row) {
      if (row.iteration == config.stop_after) InterruptGuard::flag().store(true);
    };
  }
  std::optional<int> saved_after;  // the iteration of the last good state, once saved
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
  try {
    result = run_simulation(nodes, *inputs.tree, *inputs.spacing, options, callbacks);
  } catch (const DeviceError& e) {
    if (!saved_after) throw;
    throw DeviceError(e.what() + saved_note() + " (with --device host if the device stays unusable)");
  } catch (const SimulationError& e) {
    if (!saved_after) throw;
    throw SimulationError(e.what() + saved_note());
  }
  if (result.stopped || InterruptGuard::flag().load()) {
    write_checkpoint(checkpoint_file, Checkpoint{case_identity(config), nodes, result.state});
    progress(config, "simulation: stopped after iteration {} of {}; wrote {} (continue with --resume {})",
             result.state.iterations_done, options.iterations, checkpoint_file.string(), config.out_dir.string());
  } else {
    // A checkpoint in DIR means the run there is unfinished; this one finished.
    std::error_code ec;
    fs::remove(checkpoint_file, ec);
  }
  if (result.converged)
    progress(config, "simulation: converged after {} iterations (of at most {})", result.state.iterations_done,
             options.iterations);
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
  timer.stop();
  phases.note("iterations", result.state.iterations_done);
  phases.note("converged", result.converged ? 1 : 0);
  phases.note("simulation_seconds", st.seconds);
  const fs::path& dir = config.out_dir;
  {
    const auto csv_timer = phases.phase("history.csv");
    write_history_csv(dir / "history.csv", result.history);
  }
  if (config.output.wants("png")) {
    phases.picture("history.png", [path = dir / "history.png", rows = result.history,
                                   title = fmt::format("{} ({})", config.name, method_name(config.init.method))] {
      write_history_plot(path, rows, title);
    });
  }
  write_node_outputs(config, inputs, nodes, "final",
                     fmt::format("{} - final distribution ({}, {} iterations)", config.name,
                                 method_name(config.init.method), result.state.iterations_done),
                     nullptr, phases);
  return result;
}

Mesh mesh_and_measure(const CaseConfig& config, const MeshInputs& inputs, const NodeSet& nodes, RunPhases* run) {
  RunPhases local(false);
  RunPhases& phases = run ? *run : local;
  auto timer = phases.phase("triangulation");
  Mesh mesh = triangulate(nodes, inputs.curve_names());
  timer.stop();
  progress(config, "triangulation: {} triangles", mesh.triangles.size());
  phases.note("nodes", static_cast<double>(nodes.size()));
  phases.note("triangles", static_cast<double>(mesh.triangles.size()));
  if (config.check) {
    const auto check_timer = phases.phase("check");
    // The mesh covers the polygons through the boundary nodes, which cut the curves' corners
    // where nodes have slid off geometry vertices; that area is what the check compares against.
    const double node_area = node_domain_area(nodes, inputs.geometry);
    const CheckReport report = check_mesh(mesh, node_area);
    if (!report.ok()) throw SimulationError("the mesh failed its invariant check:\n" + report.summary());
    progress(config, "mesh check: passed (topology, orientation, constrained Delaunay, boundary edges, area {:.10g}; "
             "the geometry's area is {:.10g}, relative difference {:.2g})",
             node_area, inputs.geometry.area, std::fabs(node_area - inputs.geometry.area) / inputs.geometry.area);
  }
  auto quality_timer = phases.phase("quality");
  const std::vector<TriangleQuality> per_triangle = triangle_qualities(mesh);
  QualitySummary summary = summarize_quality(per_triangle);
  summary.points = mesh.points.size();
  quality_timer.stop();
  // The pictures are drawn on the background thread while the quality is measured and the files are
  // written; the mesh and the values stay alive until the wait below (also when something throws).
  std::vector<double> values;
  const PictureGuard guard(phases);
  MeshPictureOptions picture;
  picture.title = fmt::format("{} - mesh ({} triangles)", config.name, mesh.triangles.size());
  if (config.output.color_by != "none") {
    values = metric_values(per_triangle, config.output.color_by);
    picture.triangle_values = &values;
    picture.value_label = config.output.color_by;
  }
  const fs::path& dir = config.out_dir;
  std::vector<std::string> pictures;
  const auto draw = [&](const std::string& file, const MeshPictureOptions& options) {
    phases.picture(file, [&mesh, options, path = dir / file] { write_mesh_picture(path, mesh, options); });
    pictures.push_back(file);
  };
  if (config.output.wants("png")) {
    draw("mesh.png", picture);
    for (const ViewWindow& view : config.output.views) {
      MeshPictureOptions zoomed = picture;
      zoomed.title += " - " + view.name;
      zoomed.window = view.window;
      draw(fmt::format("mesh_{}.png", view.name), zoomed);
    }
  }
  if (config.output.wants("svg") && mesh.triangles.size() <= 2 * kSvgNodeLimit) draw("mesh.svg", picture);
  {
    const auto conformance_timer = phases.phase("spacing conformance");
    const SpacingField& spacing = *inputs.spacing;
    summary.has_spacing = true;
    summary.spacing = spacing_conformance(
        mesh, [&spacing](const std::vector<Vec2>& p, std::vector<double>& q) { spacing.at_many(p, q); });
  }
  if (!config.quiet) fmt::print("{}", format_quality_table(summary, config.name));
  {
    const auto json_timer = phases.phase("quality.json");
    write_quality_json(summary, dir, config.name);
  }
  std::vector<fs::path> written;
  for (const std::string& f : config.output.formats) {
    if (!is_mesh_format(f)) continue;
    const auto writer_timer = phases.phase(fmt::format("mesh {}", f));
    for (fs::path& p : write_mesh(mesh, dir, "mesh", {f})) written.push_back(std::move(p));
  }
  {
    const auto wait_timer = phases.phase("waiting for pictures");
    phases.wait_pictures();
  }
  std::string names;
  for (const auto& p : written) names += (names.empty() ? "" : ", ") + p.filename().string();
  progress(config, "mesh: {} triangles; wrote {}/quality.json{}{}{}", mesh.triangles.size(), dir.string(),
           names.empty() ? "" : ", ", names, pictures.empty() ? "" : fmt::format(", {}", fmt::join(pictures, ", ")));
  return mesh;
}

namespace {

// `--resume`: the node set and driver state come from the checkpoint instead of the initialization
// (whose outputs the interrupted run already wrote).
void resume_mesh(const CaseConfig& config, const MeshInputs& inputs, RunPhases& phases) {
  auto timer = phases.phase("checkpoint");
  Checkpoint checkpoint = read_checkpoint_for(*config.resume, config, *inputs.tree);
  timer.stop();
  {
    const auto estimate_timer = phases.phase("estimate");
    check_node_limit(config, inputs);
  }
  prepare_output_directory(config);
  NodeSet nodes = std::move(checkpoint.nodes);
  const PictureGuard guard(phases);
  simulate(config, inputs, nodes, &checkpoint.state, &phases);
  mesh_and_measure(config, inputs, nodes, &phases);
}

// The summary line, and the JSON when --timings asks for it.
void report_phases(const CaseConfig& config, const RunPhases& phases) {
  progress(config, "{}", phases.summary());
  if (config.timings_file) write_file_atomically(*config.timings_file, phases.json());
}

}  // namespace

int run_mesh(const CaseConfig& config) {
  RunPhases phases;
  // SIGINT/SIGTERM from here on stop the simulation after its current iteration (exit 130).
  InterruptGuard interrupt;
  // Stage 1: inputs.
  auto timer = phases.phase("read");
  const MeshInputs inputs(config);
  timer.stop();
  progress(config, "geometry: {} curves, {} segments, {} loops, area {:.6g}", inputs.geometry.curves.size(),
           inputs.geometry.segments.size(), inputs.geometry.loops.size(), inputs.geometry.area);
  // An explicit OpenCL device that is not there is bad input: refuse it before anything is written.
  if (config.simulation.iterations > 0 && config.simulation.device != "host" && config.simulation.device != "auto")
    (void)ocl::select_device(config.simulation.device);
  if (config.resume) {
    resume_mesh(config, inputs, phases);
    report_phases(config, phases);
    return InterruptGuard::flag().load() ? kExitInterrupted : kExitOk;
  }
  // Stage 2: limits, before any large allocation. The estimate is part of the initialization's time
  // (the thesis' initialization also estimates the node count).
  timer = phases.phase("estimate");
  const double estimate = check_node_limit(config, inputs);
  timer.stop();
  // Stage 3: initial distribution.
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
  NodeSet nodes = initial.nodes;
  // The initial pictures read `initial` while the simulation moves `nodes`.
  const PictureGuard guard(phases);
  write_initial_outputs(config, inputs, initial, &phases);
  // Stage 5: the simulation (none with --iterations 0: the initial distribution is meshed).
  if (config.simulation.iterations > 0) simulate(config, inputs, nodes, nullptr, &phases);
  // Stage 6: the mesh, its quality and its files.
  mesh_and_measure(config, inputs, nodes, &phases);
  report_phases(config, phases);
  return InterruptGuard::flag().load() ? kExitInterrupted : kExitOk;
}

}  // namespace pdmesh
