// `pdmesh mesh`, the outputs: the output directory, the node files and pictures of a stage, the spacing
// picture, and stage mesh (triangulation, check, cleanup, quality, mesh files and pictures).
#include "app/pipeline/mesh_pipeline.hpp"
#include "app/pipeline/mesh_handover.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fmt/format.h>

#include "app/pipeline/pipeline_detail.hpp"
#include "app/pipeline/output_guard.hpp"
#include "cleanup/cleanup.hpp"
#include "cleanup/metric_cleanup.hpp"
#include "cleanup/strip_sweeps.hpp"
#include "core/atomic_file.hpp"
#include "core/errors.hpp"
#include "core/g17.hpp"
#include "core/parallel.hpp"
#include "io/mesh_formats.hpp"
#include "mesh/mesh_check.hpp"
#include "io/quality_report.hpp"
#include "io/region_quality.hpp"
#include "mesh/metric_delaunay.hpp"
#include "mesh/metric_quality.hpp"
#include "mesh/quality_sum.hpp"
#include "mesh/region_tags.hpp"
#include "mesh/triangulate_nodes.hpp"
#include "spacing/metric_complexity.hpp"
#include "nodes/node_domain.hpp"
#include "nodes/node_file.hpp"
#include "geometry/heal_report.hpp"
#include "render/heal_picture.hpp"
#include "render/mesh_picture.hpp"
#include "render/metric_picture.hpp"
#include "render/node_picture.hpp"
#include "render/spacing_picture.hpp"

namespace pdmesh {

namespace fs = std::filesystem;

CleanupOptions mesh_detail::cleanup_options(const CaseConfig& config) {
  CleanupOptions o;
  o.min_angle = config.cleanup.min_angle;
  o.iterations = static_cast<int>(config.cleanup.iterations);
  o.topology = config.cleanup.topology;
  o.split_boundary = config.cleanup.split_boundary;
  o.trials_per_triangle = config.cleanup.trials_per_triangle;
  o.min_trials = static_cast<double>(config.cleanup.min_trials);
  o.settled_aspect_drop = config.cleanup.settle;
  o.sharp_corners = config.cleanup.sharp_corners;
  o.polish = static_cast<int>(config.cleanup.polish);
  o.threads = static_cast<std::size_t>(config.cleanup.threads);
  o.small_strip_vertices = static_cast<std::size_t>(config.cleanup.small_strip_vertices);
  return o;
}
using mesh_detail::kSvgNodeLimit;
using mesh_detail::progress;
using mesh_detail::write_node_outputs;

namespace {

// The one place where the coordinates handed to the mesh and node file writers leave the meshing
// plane: with geometry.projection they are mapped back to lon/lat (a copy; the pipeline's stay in
// metres, and so do the pictures, q and the quality figures).
const Mesh& as_written(const MeshInputs& inputs, const Mesh& mesh, Mesh& copy) {
  if (!inputs.projection) return mesh;
  copy = mesh;
  inputs.projection->inverse(copy.points);
  return copy;
}
const NodeSet& as_written(const MeshInputs& inputs, const NodeSet& nodes, NodeSet& copy) {
  if (!inputs.projection) return nodes;
  copy = nodes;
  inputs.projection->inverse(copy.x);
  return copy;
}

}  // namespace

void prepare_output_directory(const CaseConfig& config) {
  std::error_code ec;
  fs::create_directories(config.out_dir, ec);
  if (ec || !fs::is_directory(config.out_dir)) {
    throw InputError(fmt::format("cannot create output directory '{}': {}", config.out_dir.string(),
                                 ec ? ec.message() : std::string("a file of that name exists")));
  }
  // The directory is this run's alone from here on (a run into an existing one took it earlier).
  lock_output_directory(config.out_dir);
  // A run killed while writing leaves its temporary beside the file it was writing.
  const std::size_t stale = remove_stale_temporaries(config.out_dir);
  if (stale > 0)
    progress(config, "removed {} temporary file(s) left in {} by a run that was killed while writing", stale,
             config.out_dir.string());
}

// Declared in pipeline_detail.hpp (the simulation stage writes the final nodes with it).
void mesh_detail::write_node_outputs(const CaseConfig& config, const MeshInputs& inputs, const NodeSet& nodes,
                                     const std::string& stage, const std::string& title,
                                     const std::vector<Box>* tree_quads, RunPhases& run,
                                     const std::shared_ptr<const void>& keep) {
  const fs::path& dir = config.out_dir;
  {
    const auto timer = run.phase(stage + ".nodes");
    NodeSet copy;
    write_node_file(dir / (stage + ".nodes"), as_written(inputs, nodes, copy), inputs.curve_names());
  }
  NodePictureOptions picture;
  picture.title = title;
  picture.tree_quads = tree_quads;
  const Geometry* geometry = &inputs.node_geometry();
  const NodeSet* drawn = &nodes;
  std::vector<std::string> names;
  const auto draw = [&](const std::string& file, const NodePictureOptions& options) {
    run.picture(file, [geometry, drawn, options, keep, path = dir / file] {
      write_node_picture(path, *geometry, *drawn, options);
    });
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

void write_spacing_picture(const CaseConfig& config, const MeshInputs& inputs, const SpacingStage& spacing) {
  const BackgroundSpacing& field = spacing.background();
  SpacingPictureOptions picture;
  picture.title = fmt::format("{} - spacing field", config.name);
  picture.value_scale = 1.0 / spacing.relax_scale();
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

// Declared in pipeline_detail.hpp (the layered run queues its merged mesh's pictures with it).
std::vector<std::string> mesh_detail::queue_mesh_views(const CaseConfig& config, const Mesh& mesh,
                                                       const MeshPictureOptions& picture, RunPhases& run,
                                                       const std::shared_ptr<const void>& keep) {
  std::vector<std::string> pictures;
  if (!config.output.wants("png")) return pictures;
  const auto draw = [&](const std::string& file, const MeshPictureOptions& options) {
    run.picture(file,
                [&mesh, options, keep, path = config.out_dir / file] { write_mesh_picture(path, mesh, options); });
    pictures.push_back(file);
  };
  draw("mesh.png", picture);
  for (const ViewWindow& view : config.output.views) {
    MeshPictureOptions zoomed = picture;
    zoomed.title += " - " + view.name;
    zoomed.window = view.window;
    draw(fmt::format("mesh_{}.png", view.name), zoomed);
  }
  return pictures;
}

namespace {

// The initial distribution's outputs, the pictures queued on `run` holding `keep` (if set).
void write_initial_node_outputs(const CaseConfig& config, const MeshInputs& inputs, const InitialDistribution& initial,
                                RunPhases& run, const std::shared_ptr<const void>& keep) {
  write_node_outputs(config, inputs, initial.nodes, "initial",
                     fmt::format("{} - initial distribution ({})", config.name, to_string(config.init.method)),
                     config.output.tree_overlay ? &initial.tree_quads : nullptr, run, keep);
}

}  // namespace

void write_initial_outputs(const CaseConfig& config, const MeshInputs& inputs, const InitialDistribution& initial,
                           RunPhases* run) {
  RunPhases local(false);
  write_initial_node_outputs(config, inputs, initial, run ? *run : local, nullptr);
}

void write_initial_outputs(const CaseConfig& config, const MeshInputs& inputs,
                           const std::shared_ptr<const InitialDistribution>& initial, RunPhases& run) {
  write_initial_node_outputs(config, inputs, *initial, run, initial);
}

namespace {

// --check: the invariant checker on `mesh`, whose boundary nodes are those of `nodes`.
void check_or_throw(const CaseConfig& config, const MeshInputs& inputs, const Mesh& mesh, const NodeSet& nodes,
                    const char* which) {
  // The mesh covers the polygons through the boundary nodes, which cut the curves' corners
  // where nodes have slid off geometry vertices; that area is what the check compares against.
  const double node_area = node_domain_area(nodes, inputs.node_geometry());
  const CheckReport report = check_mesh(mesh, node_area);
  if (!report.ok())
    throw SimulationError(fmt::format("the {} failed its invariant check:\n{}", which, report.summary()));
  progress(config,
           "mesh check ({}): passed (topology, orientation, constrained Delaunay, boundary edges, area {:.10g}; "
           "the geometry's area is {:.10g}, relative difference {:.2g})",
           which, node_area, inputs.geometry.area, std::fabs(node_area - inputs.geometry.area) / inputs.geometry.area);
}

// --check for a mesh made in a metric: every invariant of check_mesh but the Delaunay test, which a
// mesh that is Delaunay in the metric (or cleaned in it) need not pass.
void check_metric_or_throw(const CaseConfig& config, const MeshInputs& inputs, const Mesh& mesh, const NodeSet& nodes,
                           const char* which) {
  const double node_area = node_domain_area(nodes, inputs.node_geometry());
  CheckReport report = check_mesh(mesh, node_area);
  std::erase_if(report.problems, [](const std::string& p) { return p.rfind("delaunay: ", 0) == 0; });
  if (!report.ok())
    throw SimulationError(fmt::format("the {} failed its invariant check:\n{}", which, report.summary()));
  progress(config,
           "mesh check ({}): passed (topology, orientation, boundary edges, area {:.10g}; not the isotropic "
           "Delaunay test, for a mesh made in a metric)",
           which, node_area);
}

// The quality summary of the mesh's triangles (summarize_quality_of), with the smallest and largest
// angle and the triangles below `target` degrees. The triangles are measured a block at a time on up
// to `threads` threads (the cleanup's setting, 0 as the cleanup reads it) and added up on one thread
// in triangle order, so the sums are those of one thread; no per-triangle array is kept.
QualitySummary angle_figures(const Mesh& mesh, double target, double& min_angle, double& max_angle, std::size_t& below,
                             std::size_t threads = 0) {
  constexpr std::size_t kBlock = 1 << 16;
  QualityAccumulator sum;
  below = 0;
  std::vector<TriangleQuality> block;
  for (std::size_t begin = 0; begin < mesh.triangles.size(); begin += kBlock) {
    block.resize(std::min(kBlock, mesh.triangles.size() - begin));
    parallel_for(
        block.size(),
        [&](std::size_t k) {
          const auto& tri = mesh.triangles[begin + k];
          block[k] = triangle_quality(mesh.points[tri[0]], mesh.points[tri[1]], mesh.points[tri[2]]);
        },
        8192, cleanup::sweep_thread_limit(threads));
    for (const TriangleQuality& t : block) {
      sum.add(t);
      below += t.min_angle < target;
    }
  }
  const QualitySummary s = sum.summary();
  min_angle = s.min_angle;
  max_angle = s.max_angle;
  return s;
}

}  // namespace

namespace {

// The triangulation of `nodes` (or `triangulated`, when it is theirs), checked when config.check.
// With a metric field (`metrics` the metric at each node), the constrained Delaunay triangulation in
// the metric (triangulate_in_metric).
// `owner`, when given, holds `triangulated` and is reset once it has been copied.
Mesh triangulate_nodes(const CaseConfig& config, const MeshInputs& inputs, const NodeSet& nodes, RunPhases& phases,
                       const Mesh* triangulated, std::shared_ptr<const Mesh>* owner,
                       const std::vector<Metric>* metrics) {
  auto timer = phases.phase("triangulation");
  Mesh mesh;
  if (metrics != nullptr) {
    MetricDelaunayStats stats;
    mesh = triangulate_in_metric(nodes, inputs.curve_names(), *metrics, {}, &stats);
    timer.stop();
    progress(config, "triangulation in the metric: {} flips{}", stats.flips,
             stats.converged ? "" : fmt::format(" (stopped by the bound of {} flips)", stats.max_flips));
    phases.note("metric flips", static_cast<double>(stats.flips));
  } else if (triangulated && triangulates(*triangulated, nodes)) {
    mesh = *triangulated;  // the convergence rule's last measurement: the same mesh
    mesh.curve_names = inputs.curve_names();
  } else {
    mesh = triangulate(nodes, inputs.curve_names());
  }
  if (owner) owner->reset();
  timer.stop();
  progress(config, "triangulation: {} triangles", mesh.triangles.size());
  phases.note("nodes", static_cast<double>(nodes.size()));
  phases.note("triangles", static_cast<double>(mesh.triangles.size()));
  if (config.check && metrics != nullptr) {
    const auto check_timer = phases.phase("check");
    check_metric_or_throw(config, inputs, mesh, nodes, "triangulation in the metric");
  } else if (config.check) {
    const auto check_timer = phases.phase("check");
    check_or_throw(config, inputs, mesh, nodes, "triangulation");
  }
  return mesh;
}

// The final cleanup (docs/cleanup.md) of `mesh` in place; its nodes, its effect and the cleaned
// mesh's qualities.
struct CleanedMesh {
  NodeSet nodes;
  CleanupEffect effect;
  QualitySummary quality;  // of the cleaned mesh's triangles (summarize_quality_of)
};

// Where the cleanup's wall time went, as notes of the timings file (CleanupStats; docs/cli.md).
void note_cleanup_parts(const CleanupStats& stats, RunPhases& phases) {
  phases.note("cleanup_seconds", stats.seconds);
  phases.note("cleanup_iterations", stats.iterations_run);
  phases.note("cleanup_setup_seconds", stats.setup_seconds);
  phases.note("cleanup_smoothing_seconds", stats.smoothing_seconds);
  phases.note("cleanup_strips", stats.strips);
  phases.note("cleanup_strips_parallel_seconds", stats.strip_seconds);
  phases.note("cleanup_strips_serial_seconds", stats.strip_serial_seconds);
  phases.note("cleanup_strips_taken", static_cast<double>(stats.strip_taken));
  phases.note("cleanup_strips_left", static_cast<double>(stats.strip_left));
  phases.note("cleanup_topology_seconds", stats.topology_seconds);
  phases.note("cleanup_lists_seconds", stats.list_seconds);
  phases.note("cleanup_finish_seconds", stats.finish_seconds);
}

CleanedMesh clean_up(const CaseConfig& config, const MeshInputs& inputs, const SpacingStage& spacing, Mesh& mesh,
                     const NodeSet& nodes, RunPhases& phases) {
  const auto cleanup_timer = phases.phase("cleanup");
  const CleanupOptions options = mesh_detail::cleanup_options(config);
  CleanedMesh out;
  CleanupEffect& effect = out.effect;
  effect.target_deg = options.min_angle;
  effect.triangles_before = mesh.triangles.size();
  effect.points_before = mesh.points.size();
  angle_figures(mesh, options.min_angle, effect.min_angle_before, effect.max_angle_before, effect.below_before,
                options.threads);
  CleanupResult cleaned = clean_mesh(mesh, nodes, inputs.node_tree(), spacing.field(), options);
  mesh = std::move(cleaned.mesh);
  // The cleaned mesh's figures, reused by the quality summary.
  out.quality = angle_figures(mesh, options.min_angle, effect.min_angle_after, effect.max_angle_after,
                              effect.below_after, options.threads);
  effect.inserted = cleaned.stats.inserted;
  effect.removed = cleaned.stats.collapsed;
  effect.moves = cleaned.stats.moves;
  effect.seconds = cleaned.stats.seconds;
  note_cleanup_parts(cleaned.stats, phases);
  progress(config,
           "cleanup: {:.3f} s; min angle {:.2f} -> {:.2f} deg, triangles below {:g} deg {} -> {}; "
           "{} node moves, {} nodes inserted, {} removed ({} triangles)",
           effect.seconds, effect.min_angle_before, effect.min_angle_after, effect.target_deg, effect.below_before,
           effect.below_after, effect.moves, effect.inserted, effect.removed, mesh.triangles.size());
  if (config.check) check_or_throw(config, inputs, mesh, cleaned.nodes, "cleaned mesh");
  out.nodes = std::move(cleaned.nodes);
  return out;
}

// The cleanup in the metric (cleanup/metric_cleanup.hpp) of a metric run's `mesh` in place, with the
// case's cleanup settings (iterations, topology, split_boundary); `metrics` becomes the metric at the
// cleaned mesh's points. The effect's angle figures are measured as for the isotropic cleanup.
CleanedMesh clean_up_in_metric(const CaseConfig& config, const MeshInputs& inputs, const SpacingStage& spacing,
                               const MetricField& metric, Mesh& mesh, const NodeSet& nodes,
                               std::vector<Metric>& metrics, RunPhases& phases) {
  const auto cleanup_timer = phases.phase("cleanup");
  MetricCleanupOptions options;
  options.iterations = static_cast<int>(config.cleanup.iterations);
  options.topology = config.cleanup.topology;
  options.split_boundary = config.cleanup.split_boundary;
  CleanedMesh out;
  CleanupEffect& effect = out.effect;
  effect.target_deg = config.cleanup.min_angle;
  effect.triangles_before = mesh.triangles.size();
  effect.points_before = mesh.points.size();
  angle_figures(mesh, effect.target_deg, effect.min_angle_before, effect.max_angle_before, effect.below_before);
  const MetricQualitySummary before = metric_quality(mesh, metrics);
  MetricCleanupResult cleaned = clean_mesh_in_metric(mesh, nodes, inputs.node_tree(), spacing.field(), metric, options);
  mesh = std::move(cleaned.mesh);
  metrics = std::move(cleaned.metrics);
  out.quality =
      angle_figures(mesh, effect.target_deg, effect.min_angle_after, effect.max_angle_after, effect.below_after);
  const cleanup::MetricOpsCounts& c = cleaned.stats.counts;
  effect.inserted = c.splits + c.boundary_splits;
  effect.removed = c.collapses + c.boundary_collapses;
  effect.moves = c.moves;
  effect.seconds = cleaned.stats.seconds;
  const MetricQualitySummary after = metric_quality(mesh, metrics);
  progress(config,
           "cleanup in the metric: {:.3f} s, {} iterations; edges in [1/sqrt2, sqrt2] {:.1f} -> {:.1f} %, Q min "
           "{:.3f} -> {:.3f}; {} splits ({} on the boundary), {} collapses ({} on the boundary), {} flips, {} node "
           "moves ({} triangles)",
           effect.seconds, cleaned.stats.iterations_run, before.window_percent, after.window_percent, before.q_min,
           after.q_min, effect.inserted, c.boundary_splits, effect.removed, c.boundary_collapses, c.flips, c.moves,
           mesh.triangles.size());
  phases.note("metric splits", static_cast<double>(effect.inserted));
  phases.note("metric collapses", static_cast<double>(effect.removed));
  if (config.check) check_metric_or_throw(config, inputs, mesh, cleaned.nodes, "mesh cleaned in the metric");
  out.nodes = std::move(cleaned.nodes);
  return out;
}

// Queues mesh.png, mesh_<view>.png and mesh.svg as output.formats asks, and for a metric run
// mesh_metric_q.png (the triangles coloured by their quality Q in the metric, 0 to 1) and metric.png
// (the metric at the points as ellipses); returns their names. `mesh`, `values`, `metric_q` and
// `metrics` must stay unchanged until the pictures are drawn.
std::vector<std::string> queue_mesh_pictures(const CaseConfig& config, const Mesh& mesh,
                                             const std::vector<double>* values, RunPhases& phases,
                                             const std::vector<double>* metric_q = nullptr,
                                             const std::vector<Metric>* metrics = nullptr) {
  MeshPictureOptions picture;
  picture.title = fmt::format("{} - mesh ({} triangles)", config.name, mesh.triangles.size());
  if (values) {
    picture.triangle_values = values;
    picture.value_label = config.output.color_by;
  }
  picture.fill_regions = config.output.color_by == "region";
  if (picture.fill_regions && mesh.region.empty())
    progress(config,
             "output.color_by = region: the geometry has no regions; the mesh pictures show every triangle "
             "as \"no region\"");
  const fs::path& dir = config.out_dir;
  std::vector<std::string> pictures = mesh_detail::queue_mesh_views(config, mesh, picture, phases);
  const auto draw = [&](const std::string& file, const MeshPictureOptions& options) {
    phases.picture(file, [&mesh, options, path = dir / file] { write_mesh_picture(path, mesh, options); });
    pictures.push_back(file);
  };
  if (config.output.wants("png")) {
    // A mesh.png too dense to show edges (millions of nearly uniform triangles) gets a close-up that does.
    if (const std::optional<CloseUp> close_up =
            dense_mesh_close_up(mesh, default_mesh_window(mesh), picture.long_side)) {
      MeshPictureOptions zoomed = picture;
      zoomed.title += fmt::format(" - around the smallest angle, {:.2f} deg", close_up->min_angle);
      zoomed.window = close_up->window;
      draw("mesh_smallest_angle.png", zoomed);
    }
  }
  if (config.output.wants("svg") && mesh.triangles.size() <= 2 * kSvgNodeLimit) draw("mesh.svg", picture);
  if (metric_q != nullptr && config.output.wants("png")) {
    MeshPictureOptions q = picture;
    q.title = fmt::format("{} - quality Q in the metric ({} triangles)", config.name, mesh.triangles.size());
    q.triangle_values = metric_q;
    q.fill_regions = false;
    q.value_label = "metric Q";
    q.value_range = std::pair{0.0, 1.0};
    draw("mesh_metric_q.png", q);
  }
  if (metrics != nullptr && config.output.wants("png")) {
    MetricPictureOptions ellipses;
    ellipses.title = fmt::format("{} - the metric", config.name);
    phases.picture("metric.png", [&mesh, metrics, ellipses, path = dir / "metric.png"] {
      write_metric_picture(path, mesh, *metrics, ellipses);
    });
    pictures.push_back("metric.png");
  }
  return pictures;
}

// The quality table, DIR/quality.json, the mesh files, mesh.nodes and the pictures of the mesh stage.
void write_mesh_outputs(const CaseConfig& config, const MeshInputs& inputs, const SpacingField& spacing,
                        const Mesh& mesh, const NodeSet& mesh_nodes, QualitySummary& summary, RunPhases& phases,
                        const std::vector<double>* metric_q, const std::vector<Metric>* metrics,
                        const std::vector<PeriodicLink>& periodic) {
  // The pictures are drawn on the background thread while the quality is measured and the files are
  // written; the mesh and the values stay alive until the wait below (also when something throws).
  std::vector<double> values;
  const PictureGuard guard(phases);
  const bool by_metric = config.output.color_by != "none" && config.output.color_by != "region";
  if (by_metric) values = mesh_metric_values(mesh, config.output.color_by);
  const std::vector<std::string> pictures =
      queue_mesh_pictures(config, mesh, by_metric ? &values : nullptr, phases, metric_q, metrics);
  const SpacingBatch q = [&spacing](const std::vector<Vec2>& p, std::vector<double>& out) { spacing.at_many(p, out); };
  {
    const auto conformance_timer = phases.phase("spacing conformance");
    summary.has_spacing = true;
    summary.spacing = spacing_conformance(mesh, q);
  }
  if (has_regions(mesh)) {
    const auto regions_timer = phases.phase("quality per region");
    add_region_quality(mesh, summary, q);
  }
  if (!config.quiet) fmt::print("{}{}", format_quality_table(summary, config.name), format_region_table(summary));
  const fs::path& dir = config.out_dir;
  {
    const auto json_timer = phases.phase("quality.json");
    write_quality_json(summary, dir, config.name,
                       inputs.healing.changes.empty() ? std::string() : heal_json(inputs.healing),
                       periodic_json(mesh.curve_names, periodic));
  }
  for (const PeriodicLink& l : periodic)
    progress(config, "periodic: '{}' -> '{}': {} node pairs, largest mismatch {:.3g}",
             mesh.curve_names[static_cast<std::size_t>(l.source_curve)],
             mesh.curve_names[static_cast<std::size_t>(l.curve)], l.nodes.size(), l.max_mismatch);
  if (!inputs.healing.changes.empty() && config.output.wants("png")) {
    const auto heal_timer = phases.phase("healing.png");
    write_heal_picture(dir / "healing.png", inputs.heal_input, inputs.healing, config.name);
  }
  std::vector<fs::path> written;
  Mesh lonlat_mesh;
  const Mesh& mesh_out = as_written(inputs, mesh, lonlat_mesh);
  for (const std::string& f : config.output.formats) {
    if (!is_mesh_format(f)) continue;
    const auto writer_timer = phases.phase(fmt::format("mesh {}", f));
    MeshWriteOptions write_options;
    write_options.open_boundaries = config.output.open_boundaries;
    write_options.periodic = &periodic;
    write_options.walls = wall_curves(config);
    for (fs::path& p : write_mesh(mesh_out, dir, "mesh", {f}, write_options)) written.push_back(std::move(p));
  }
  {
    // The nodes of the mesh with their q, kinds and curve chains (final.nodes after the cleanup; the
    // same nodes without it), for tools that need the mesh's boundary chains, like tools/eval/compare.
    const auto nodes_timer = phases.phase("mesh.nodes");
    NodeSet copy;
    write_node_file(dir / "mesh.nodes", as_written(inputs, mesh_nodes, copy), inputs.curve_names());
  }
  {
    const auto wait_timer = phases.phase("waiting for pictures");
    phases.wait_pictures();
  }
  std::string names;
  for (const std::string& name : written_names(dir, written)) names += (names.empty() ? "" : ", ") + name;
  progress(config, "mesh: {} triangles; wrote {}/quality.json, mesh.nodes{}{}{}", mesh.triangles.size(), dir.string(),
           names.empty() ? "" : ", ", names, pictures.empty() ? "" : fmt::format(", {}", fmt::join(pictures, ", ")));
}

}  // namespace

namespace {

// mesh_and_measure, with the owner of `triangulated` when the caller hands it over.
Mesh mesh_stage(const CaseConfig& config, const MeshInputs& inputs, const SpacingStage& spacing, const NodeSet& nodes,
                RunPhases* run, const Mesh* triangulated, std::shared_ptr<const Mesh>* owner) {
  RunPhases local(false);
  RunPhases& phases = run ? *run : local;
  // A metric run: the metric at every node (one thread: an expression field is not thread-safe), for
  // the triangulation in the metric and the measures.
  const MetricField* metric = spacing.metric();
  std::vector<Metric> metrics;
  if (metric != nullptr) {
    const auto metric_timer = phases.phase("metric at the nodes");
    metrics.reserve(nodes.x.size());
    for (const Vec2& p : nodes.x) metrics.push_back(metric->at(p));
  }
  Mesh mesh = triangulate_nodes(config, inputs, nodes, phases, triangulated, owner, metric ? &metrics : nullptr);
  // The final cleanup: the mesh files and pictures show the cleaned mesh; final.nodes stays the
  // simulation's result. A metric run has its own cleanup, in the metric: the isotropic one works on
  // angles and would undo the metric Delaunay's flips.
  const bool cleanup = config.cleanup.enabled;
  CleanedMesh cleaned;
  if (cleanup && metric == nullptr) cleaned = clean_up(config, inputs, spacing, mesh, nodes, phases);
  if (cleanup && metric != nullptr)
    cleaned = clean_up_in_metric(config, inputs, spacing, *metric, mesh, nodes, metrics, phases);
  const NodeSet& mesh_nodes = cleanup ? cleaned.nodes : nodes;
  // The field as asked, not the one the nodes relaxed at (spacing.relax_scale x it).
  const SpacingField& field = spacing.asked();
  // The field at every node goes into the mesh files (point data "q"): a run's field can be read back
  // with spacing.field = "mesh", or edited (e.g. scaled by a solution's error indicator) first.
  {
    const auto q_timer = phases.phase("q at the nodes");
    field.at_many(mesh.points, mesh.spacing);
  }
  mesh.region = region_tags(mesh, inputs.geometry.regions, inputs.node_geometry());
  if (!mesh.region.empty()) mesh.region_names = region_names_of(inputs.geometry.regions);
  mesh.curve_groups = curve_groups_of(inputs.geometry.groups, mesh.curve_names);
  // [[periodic]]: every pair's nodes must have come through the stages exactly.
  const std::vector<PeriodicLink> periodic = link_periodic_nodes(mesh, inputs.periodic);
  if (!config.write_outputs) return mesh;  // the Python API measures on demand (Mesh.quality())
  auto quality_timer = phases.phase("quality");
  QualitySummary summary = cleanup ? std::move(cleaned.quality) : summarize_quality_of(mesh);
  summary.points = mesh.points.size();
  list_constraints(mesh, summary);
  summary.has_cleanup = cleanup;
  summary.cleanup = cleaned.effect;
  std::vector<double> metric_q;
  if (metric != nullptr) {
    // metrics[i] is the metric at mesh.points[i]: the nodes', or the cleaned mesh's points'.
    summary.has_metric = true;
    summary.metric = metric_quality(mesh, metrics, complexity_on_mesh(mesh.points, mesh.triangles, metrics));
    metric_q = metric_qualities(mesh.points, mesh.triangles, metrics);
  }
  quality_timer.stop();
  write_mesh_outputs(config, inputs, field, mesh, mesh_nodes, summary, phases, metric != nullptr ? &metric_q : nullptr,
                     metric != nullptr ? &metrics : nullptr, periodic);
  return mesh;
}

}  // namespace

Mesh mesh_and_measure(const CaseConfig& config, const MeshInputs& inputs, const SpacingStage& spacing,
                      const NodeSet& nodes, RunPhases* run, const Mesh* triangulated) {
  return mesh_stage(config, inputs, spacing, nodes, run, triangulated, nullptr);
}

Mesh mesh_and_measure(const CaseConfig& config, const MeshInputs& inputs, const SpacingStage& spacing,
                      const NodeSet& nodes, RunPhases* run, std::shared_ptr<const Mesh>&& triangulated) {
  std::shared_ptr<const Mesh> owner = std::move(triangulated);
  return mesh_stage(config, inputs, spacing, nodes, run, owner.get(), &owner);
}

}  // namespace pdmesh
