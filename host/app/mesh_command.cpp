// The `pdmesh mesh` pipeline: read and check inputs, check limits, initialize, write outputs.
#include "app/mesh_command.hpp"

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <future>
#include <optional>
#include <fmt/format.h>

#include "app/backend_choice.hpp"
#include "app/case_spacing.hpp"
#include "app/exit_codes.hpp"
#include "app/interrupt.hpp"
#include "app/resume.hpp"
#include "cleanup/cleanup.hpp"
#include "core/atomic_file.hpp"
#include "core/errors.hpp"
#include "geometry/geometry_files.hpp"
#include "init/node_estimate.hpp"
#include "io/mesh_formats.hpp"
#include "mesh/mesh_check.hpp"
#include "mesh/quality.hpp"
#include "mesh/quality_report.hpp"
#include "mesh/triangulate_nodes.hpp"
#include "nodes/node_domain.hpp"
#include "nodes/node_file.hpp"
#include "opencl/devices.hpp"
#include "render/history_plot.hpp"
#include "render/mesh_picture.hpp"
#include "render/node_picture.hpp"
#include "render/spacing_picture.hpp"
#include "sim/convergence.hpp"
#include "sim/history.hpp"
#include "sim/population.hpp"
#include "spacing/mesh_spacing.hpp"
#include "spacing/resolution_check.hpp"

namespace pdmesh {

namespace fs = std::filesystem;

namespace {

// Every node is an element in an SVG; beyond this many the file would run to hundreds of
// megabytes, so only the PNG pictures (and zoomed views) are written.
constexpr std::size_t kSvgNodeLimit = 500'000;


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
  geometry = config.geometry.given_curves.empty()
                 ? read_geometry(files, config.geometry.curve_names, options)
                 : geometry_from_curves(config.geometry.given_curves, config.geometry.curve_names, options);
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
  spacing_options = pdmesh::spacing_options(config);
  check_spacing_options(spacing_options);
  source_ = config.source.string();
  max_nodes_ = config.max_nodes;
  const auto spacing_start = std::chrono::steady_clock::now();
  spacing = make_case_spacing(config, *tree);
  if (const auto* m = dynamic_cast<const MeshSpacing*>(spacing.get())) {
    const MeshFieldData& d = m->data();
    const auto [lo, hi] = std::minmax_element(d.q.begin(), d.q.end());
    spacing_summary = fmt::format("spacing: '{}' on {} ({} triangles, {} points, q from {:.4g} to {:.4g}), read, checked and "
                                  "indexed in {:.3f} s",
                                  d.array, d.file, d.triangles.size(), d.points.size(), *lo, *hi,
                                  std::chrono::duration<double>(std::chrono::steady_clock::now() - spacing_start).count());
  }
  // Before anything else uses them: with unresolvable coordinates the node estimate's tree could
  // refine without end.
  check_coordinate_resolution(geometry, *spacing);
  boundary_rule = config.boundary.nodes;
  if (config.geometry.curves == CurveKind::Smooth) {
    DenseOptions dense_options;
    dense_options.join_tolerance = config.geometry.join_tolerance;
    try {
      dense = std::make_unique<DenseGeometry>(
          make_dense_geometry(SmoothCurves(geometry, config.geometry.corner_angle), *spacing, dense_options));
    } catch (const GeometryError& e) {
      // Smooth curves through coarse points can cross where the polylines pass close to each other.
      smooth_fallback = e.what();
    }
    if (dense) {
      check_coordinate_resolution(dense->geometry, *spacing);
      dense_tree = std::make_unique<GeometryTree>(dense->geometry);
    }
  }
}

void MeshInputs::place_boundary() const {
  if (boundary_placed_) return;
  boundary_placed_ = true;
  // The thesis' rule (every point of the input polyline) is applied by the initialization itself.
  if (!dense && boundary_rule == BoundaryNodeRule::Input) return;
  const Geometry& on = node_geometry();
  PlacementOptions placement;
  placement.max_nodes = max_nodes_;
  // Placed by the final field (the pipeline's: graded, feature size, curvature), so that the boundary
  // rows match the interior rows next to them.
  const SpacingField& q = field();
  const CurveStations stations = boundary_rule == BoundaryNodeRule::Spacing ? spacing_stations(on, q, placement)
                                                                            : vertex_stations(on, &dense->vertex);
  boundary_ = assemble_boundary_nodes(on, q, stations);
  resolution_ = station_resolution(on, stations);
}

const NodeSet* MeshInputs::boundary_nodes() const {
  place_boundary();
  return boundary_ ? &*boundary_ : nullptr;
}

const std::vector<double>* MeshInputs::segment_resolution() const {
  place_boundary();
  return resolution_.empty() ? nullptr : &resolution_;
}

SpacingOptions spacing_options(const CaseConfig& config) {
  SpacingOptions o;
  o.scale = config.spacing.scale;
  o.gradation = config.spacing.gradation;
  o.rows_in_gap = config.spacing.rows_in_gap;
  o.curvature_angle = config.spacing.curvature_angle;
  // The sources' floor stays with boundary nodes placed by the field too: without it the feature size
  // asks for q -> 0 toward sharp V tips, whose placed nodes then crowd into slivers (measured on the
  // corpus: heatsink_channel 0.22 deg, coastline 0.47 deg without; docs/spacing.md). The final floor
  // only serves input points as boundary nodes: placed nodes follow whatever finer field the case asks.
  o.input_boundary_floor = kInputBoundaryFloor;
  o.final_floor = config.boundary.nodes == BoundaryNodeRule::Input;
  return o;
}

namespace {

// The hexagonal-packing estimate against --max-nodes.
void refuse_above_limit(const std::string& source, std::uint64_t max_nodes, double estimate, const char* which) {
  if (!std::isfinite(estimate) || estimate > static_cast<double>(max_nodes)) {
    throw LimitError(fmt::format("{}: the {} asks for about {:.0f} nodes (hexagonal-packing estimate), "
                                 "more than --max-nodes {}; coarsen the spacing or raise --max-nodes",
                                 source, which, estimate, max_nodes));
  }
}

}  // namespace

const SpacingPipeline& MeshInputs::pipeline() const {
  if (!pipeline_) {
    // The base field's quadtree is checked before the limits refine it (they only lower q).
    const auto check_base = [this](const BackgroundSpacing& base_tree) {
      refuse_above_limit(source_, max_nodes_, estimate_node_count(*tree, base_tree), "spacing field before its limits");
    };
    pipeline_ = std::make_unique<SpacingPipeline>(*spacing, *tree, spacing_options,
                                                  spacing_options.modifies() ? check_base : SpacingPipeline::BaseCheck{});
    // The sources lower q: the final field must be resolvable too.
    if (!pipeline_->exact()) check_coordinate_resolution(geometry, pipeline_->field());
  }
  return *pipeline_;
}

std::vector<std::string> MeshInputs::curve_names() const {
  std::vector<std::string> names;
  for (const Curve& c : geometry.curves) names.push_back(c.name);
  return names;
}

double check_node_limit(const CaseConfig& config, const MeshInputs& inputs) {
  // One pass over the leaves of the final field's quadtree (init/node_estimate), which the simulation
  // samples anyway: per-sample queries over the initialization tree took longer than the simulation
  // on rods_fine (7.4 s against 5.5 s, thesis preset).
  const double estimate = estimate_node_count(inputs.node_tree(), inputs.pipeline().background());
  refuse_above_limit(config.source.string(), config.max_nodes, estimate, "spacing field");
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
  options.boundary = inputs.boundary_nodes();
  options.segment_resolution = inputs.segment_resolution();
  return make_initial_distribution(inputs.node_tree(), inputs.field(), options);
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
  const Geometry* geometry = &inputs.node_geometry();
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

void write_spacing_picture(const CaseConfig& config, const MeshInputs& inputs) {
  const BackgroundSpacing& field = inputs.pipeline().background();
  SpacingPictureOptions picture;
  picture.title = fmt::format("{} - spacing field", config.name);
  write_spacing_picture(config.out_dir / "spacing.png", *inputs.tree, field, picture);
  for (const ViewWindow& view : config.output.views) {
    SpacingPictureOptions zoomed = picture;
    zoomed.title += " - " + view.name;
    zoomed.window = view.window;
    write_spacing_picture(config.out_dir / fmt::format("spacing_{}.png", view.name), *inputs.tree, field, zoomed);
  }
  progress(config, "wrote {}/spacing.png{}", config.out_dir.string(),
           config.output.views.empty() ? "" : fmt::format(" and {} view(s)", config.output.views.size()));
}

void write_initial_outputs(const CaseConfig& config, const MeshInputs& inputs, const InitialDistribution& initial,
                           RunPhases* run) {
  RunPhases local(false);
  write_node_outputs(config, inputs, initial.nodes, "initial",
                     fmt::format("{} - initial distribution ({})", config.name, to_string(config.init.method)),
                     config.output.tree_overlay ? &initial.tree_quads : nullptr, run ? *run : local);
}

SimOptions simulation_options(const CaseConfig& config) {
  SimOptions options;
  options.iterations = static_cast<int>(config.simulation.iterations);
  options.convergence.enabled = config.simulation.stop == StopRule::Converged;
  options.convergence.aspect_tolerance = config.simulation.stop_aspect;
  options.convergence.angle_tolerance = config.simulation.stop_angle;
  options.dt_initial = config.simulation.dt_for(config.init.method);
  options.cutoff = config.simulation.cutoff;
  options.lj_a = config.simulation.lj_a;
  options.r0_any_direction = config.simulation.r0_any_direction;
  options.stability_factor = config.simulation.stability_factor;
  options.population = config.population;
  options.quiet = config.quiet;
  return options;
}

SimResult simulate(const CaseConfig& config, const MeshInputs& inputs, NodeSet& nodes, const SimState* resume,
                   const SimulateHooks* hooks, RunPhases* run) {
  RunPhases local(false);
  RunPhases& phases = run ? *run : local;
  auto timer = phases.phase("simulation");
  // auto: the best OpenCL device whose program builds, else the host reference. An explicit opencl
  // spec that cannot be met throws InputError listing the devices (exit 2).
  const auto note = [&config](const std::string& line) { progress(config, "{}", line); };
  const ChosenBackend backend = hooks && hooks->backend
                                    ? hooks->backend(note)
                                    : choose_backend(config.simulation.device, config.simulation.precision, note);
  SimOptions options = simulation_options(config);
  options.stop = hooks && hooks->stop ? hooks->stop : &InterruptGuard::flag();
  options.resume = resume;
  // The pipeline's quadtree: the final field itself, or (thesis) eq. 3.6's lookup table, built here.
  // (run_mesh builds it in its "spacing" phase, for the node estimate too.)
  const SpacingPipeline& pipeline = inputs.pipeline();
  // Smooth curves: the nodes live on the dense polyline, so the simulator builds its quadtree (leaves
  // tagged inside/boundary/outside) of the final field over that geometry instead.
  options.background = inputs.dense ? nullptr : &pipeline.background();
  progress(config, "simulation: {}{} iterations on {}, cutoff {}, a = {}, r0 rule {}, stability factor {}",
           options.convergence.enabled ? "until converged, at most " : "", options.iterations,
           backend.simulator->describe(), options.cutoff, options.lj_a,
           options.r0_any_direction ? "any_direction" : "force_direction", options.stability_factor);
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
  try {
    result = backend.simulator->run(nodes, inputs.node_tree(), inputs.field(), options, callbacks);
  } catch (const DeviceError& e) {
    if (!saved_after) throw;
    throw DeviceError(e.what() + saved_note() + " (with --device host if the device stays unusable)");
  } catch (const SimulationError& e) {
    if (!saved_after) throw;
    throw SimulationError(e.what() + saved_note());
  }
  if (!config.write_outputs) return result;  // the Python API keeps the state in memory
  if (result.stopped || InterruptGuard::flag().load()) {
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

// --check: the invariant checker on `mesh`, whose boundary nodes are those of `nodes`.
void check_or_throw(const CaseConfig& config, const MeshInputs& inputs, const Mesh& mesh, const NodeSet& nodes,
                    const char* which) {
  // The mesh covers the polygons through the boundary nodes, which cut the curves' corners
  // where nodes have slid off geometry vertices; that area is what the check compares against.
  const double node_area = node_domain_area(nodes, inputs.node_geometry());
  const CheckReport report = check_mesh(mesh, node_area);
  if (!report.ok()) throw SimulationError(fmt::format("the {} failed its invariant check:\n{}", which, report.summary()));
  progress(config, "mesh check ({}): passed (topology, orientation, constrained Delaunay, boundary edges, area {:.10g}; "
           "the geometry's area is {:.10g}, relative difference {:.2g})",
           which, node_area, inputs.geometry.area, std::fabs(node_area - inputs.geometry.area) / inputs.geometry.area);
}

// Smallest and largest angle and the triangles below `target` degrees.
void angle_figures(const std::vector<TriangleQuality>& per_triangle, double target, double& min_angle,
                   double& max_angle, std::size_t& below) {
  const QualitySummary s = summarize_quality(per_triangle);
  min_angle = s.min_angle;
  max_angle = s.max_angle;
  below = 0;
  for (const TriangleQuality& t : per_triangle) below += t.min_angle < target;
}

}  // namespace

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
    check_or_throw(config, inputs, mesh, nodes, "triangulation");
  }
  // The final cleanup (docs/cleanup.md): the mesh files and pictures show the cleaned mesh; final.nodes
  // stays the simulation's result.
  CleanupEffect effect;
  std::vector<TriangleQuality> per_triangle;  // the final mesh's, computed once
  NodeSet cleaned_nodes;
  const NodeSet* mesh_nodes = &nodes;
  if (config.cleanup.enabled) {
    const auto cleanup_timer = phases.phase("cleanup");
    CleanupOptions options;
    options.min_angle = config.cleanup.min_angle;
    options.iterations = static_cast<int>(config.cleanup.iterations);
    options.topology = config.cleanup.topology;
    options.split_boundary = config.cleanup.split_boundary;
    effect.target_deg = options.min_angle;
    effect.triangles_before = mesh.triangles.size();
    effect.points_before = mesh.points.size();
    angle_figures(triangle_qualities(mesh), options.min_angle, effect.min_angle_before, effect.max_angle_before,
                  effect.below_before);
    CleanupResult cleaned = clean_mesh(mesh, nodes, inputs.node_tree(), inputs.field(), options);
    mesh = std::move(cleaned.mesh);
    per_triangle = triangle_qualities(mesh);  // the cleaned mesh's, reused by the quality summary below
    angle_figures(per_triangle, options.min_angle, effect.min_angle_after, effect.max_angle_after, effect.below_after);
    effect.inserted = cleaned.stats.inserted;
    effect.removed = cleaned.stats.collapsed;
    effect.moves = cleaned.stats.moves;
    effect.seconds = cleaned.stats.seconds;
    progress(config, "cleanup: {:.3f} s; min angle {:.2f} -> {:.2f} deg, triangles below {:g} deg {} -> {}; "
             "{} node moves, {} nodes inserted, {} removed ({} triangles)",
             effect.seconds, effect.min_angle_before, effect.min_angle_after, effect.target_deg, effect.below_before,
             effect.below_after, effect.moves, effect.inserted, effect.removed, mesh.triangles.size());
    if (config.check) check_or_throw(config, inputs, mesh, cleaned.nodes, "cleaned mesh");
    cleaned_nodes = std::move(cleaned.nodes);
    mesh_nodes = &cleaned_nodes;
  }
  const SpacingField& spacing = inputs.field();
  // The field at every node goes into the mesh files (point data "q"): a run's field can be read back
  // with spacing.field = "mesh", or edited (e.g. scaled by a solution's error indicator) first.
  {
    const auto q_timer = phases.phase("q at the nodes");
    spacing.at_many(mesh.points, mesh.spacing);
  }
  if (!config.write_outputs) return mesh;  // the Python API measures on demand (Mesh.quality())
  auto quality_timer = phases.phase("quality");
  if (!config.cleanup.enabled) per_triangle = triangle_qualities(mesh);
  QualitySummary summary = summarize_quality(per_triangle);
  summary.points = mesh.points.size();
  summary.has_cleanup = config.cleanup.enabled;
  summary.cleanup = effect;
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
    // The nodes of the mesh with their q, kinds and curve chains (final.nodes after the cleanup; the
    // same nodes without it), for tools that need the mesh's boundary chains, like tools/compare.
    const auto nodes_timer = phases.phase("mesh.nodes");
    write_node_file(dir / "mesh.nodes", *mesh_nodes, inputs.curve_names());
  }
  {
    const auto wait_timer = phases.phase("waiting for pictures");
    phases.wait_pictures();
  }
  std::string names;
  for (const auto& p : written) names += (names.empty() ? "" : ", ") + p.filename().string();
  progress(config, "mesh: {} triangles; wrote {}/quality.json, mesh.nodes{}{}{}", mesh.triangles.size(), dir.string(),
           names.empty() ? "" : ", ", names, pictures.empty() ? "" : fmt::format(", {}", fmt::join(pictures, ", ")));
  return mesh;
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

// `--resume`: the node set and driver state come from the checkpoint instead of the initialization
// (whose outputs the interrupted run already wrote).
void resume_mesh(const CaseConfig& config, const MeshInputs& inputs, RunPhases& phases) {
  auto timer = phases.phase("checkpoint");
  Checkpoint checkpoint = read_checkpoint_for(*config.resume, config, inputs.node_tree());
  timer.stop();
  {
    const auto spacing_timer = phases.phase("spacing");
    (void)inputs.pipeline().background();
  }
  {
    const auto estimate_timer = phases.phase("estimate");
    check_node_limit(config, inputs);
  }
  report_spacing(config, inputs);
  prepare_output_directory(config);
  NodeSet nodes = std::move(checkpoint.nodes);
  const PictureGuard guard(phases);
  simulate(config, inputs, nodes, &checkpoint.state, nullptr, &phases);
  mesh_and_measure(config, inputs, nodes, &phases);
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
  if (!inputs.spacing_summary.empty()) progress(config, "{}", inputs.spacing_summary);
  if (inputs.dense)
    progress(config, "geometry: smooth curves (centripetal Catmull-Rom) as a dense polyline of {} segments, area {:.6g}",
             inputs.dense->geometry.segments.size(), inputs.dense->geometry.area);
  if (!inputs.smooth_fallback.empty())
    progress(config, "note: geometry.curves = \"smooth\" fell back to the input polylines: {}", inputs.smooth_fallback);
  // An explicit OpenCL device that is not there is bad input: refuse it before anything is written.
  if (config.simulation.iterations > 0 && config.simulation.device != "host" && config.simulation.device != "auto")
    (void)ocl::select_device(config.simulation.device);
  if (config.resume) {
    resume_mesh(config, inputs, phases);
    report_phases(config, phases);
    return InterruptGuard::flag().load() ? kExitInterrupted : kExitOk;
  }
  // The simulation's backend (OpenCL platforms, context, program from PoCL's cache: ~0.05 s wall on
  // 30P30N) is set up on a thread while this one builds the spacing field, estimates and fills, which
  // leave a core idle part of the time. Its notes and errors come out when the simulation starts.
  std::future<PreparedBackend> prepared;
  if (config.simulation.iterations > 0)
    prepared = std::async(std::launch::async, [&config] { return prepare_backend(config); });
  // Stage 2: the final spacing field (the pipeline), then the limits, before any large allocation.
  // The quadtree of the final field (in the thesis preset eq. 3.6's lookup table, which the node
  // estimate and the simulation read) is built here.
  timer = phases.phase("spacing");
  (void)inputs.pipeline().background();
  timer.stop();
  report_spacing(config, inputs);
  timer = phases.phase("estimate");
  const double estimate = check_node_limit(config, inputs);
  timer.stop();
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
  if (config.simulation.iterations > 0) {
    SimulateHooks hooks;
    hooks.backend = [&prepared](const std::function<void(const std::string&)>& note) {
      PreparedBackend p = prepared.get();
      for (const std::string& line : p.notes) note(line);
      if (p.error) std::rethrow_exception(p.error);
      return std::move(p.backend);
    };
    simulate(config, inputs, nodes, nullptr, &hooks, &phases);
  }
  // Stage 6: the mesh, its quality and its files.
  mesh_and_measure(config, inputs, nodes, &phases);
  report_phases(config, phases);
  return InterruptGuard::flag().load() ? kExitInterrupted : kExitOk;
}

}  // namespace pdmesh
