// `pdmesh mesh`, stages read, spacing and initial (mesh_inputs.hpp): the inputs (geometry, trees, base
// field), the spacing pipeline and the limits, the boundary placement and the initial distribution.
#include "app/pipeline/mesh_inputs.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <memory>
#include <set>
#include <string_view>
#include <fmt/format.h>
#include <fmt/ranges.h>

#include "app/config/case_spacing.hpp"
#include "core/errors.hpp"
#include "core/memory_budget.hpp"
#include "geometry/farfield.hpp"
#include "geometry/geometry_files.hpp"
#include "geometry/geometry_tree.hpp"
#include "geometry/smooth_embedded.hpp"
#include "init/kept_nodes.hpp"
#include "init/metric_fill.hpp"
#include "layers/boundary_layers.hpp"
#include "io/mesh_geometry.hpp"
#include "spacing/short_arcs.hpp"
#include "init/node_estimate.hpp"
#include "init/warm_points.hpp"
#include "spacing/mesh_spacing.hpp"
#include "spacing/spacing_field.hpp"
#include "spacing/refine_regions.hpp"
#include "spacing/scaled_spacing.hpp"
#include "spacing/resolution_check.hpp"

namespace pdmesh {

namespace {

// geometry.heal: the step that heals the raw curves at the mesh's resolution, judged by eq. 3.6's
// spacing on them (heal.hpp), recording in `in` what it changed; the spacing field is then built on
// the healed geometry. Empty when healing is off.
PrepareCurves healing_step(const CaseConfig& config, MeshInputs& in) {
  if (!config.geometry.heal) return {};
  return [&in, &config](std::vector<RawCurve>& curves, const std::vector<RawHolePoint>& holes) {
    std::vector<std::vector<Vec2>> before;
    for (const RawCurve& c : curves) before.push_back(c.points);
    HealOptions heal;
    heal.scale = config.spacing.scale;
    if (config.spacing.size > 0.0) {
      heal.size = [size = config.spacing.size](Vec2) { return size; };
    } else if (config.spacing.field == SpacingKind::Expression) {
      auto expression = std::make_shared<ExpressionSpacing>(config.spacing.expression);
      heal.size = [expression](Vec2 p) { return expression->at(p); };
    }
    heal.join_tolerance = config.geometry.join_tolerance;
    for (const RawHolePoint& h : holes) heal.holes.push_back(h.p);
    in.healing = heal_curves(curves, heal);
    if (!in.healing.changes.empty()) in.heal_input = std::move(before);
  };
}

// The regions given in memory (the Python API) into the geometry: each point inside the domain and on
// no curve (a point on a curve lies between two regions), else InputError naming it by its label.
void add_given_regions(const CaseConfig& config, Geometry& geometry) {
  if (config.geometry.given_regions.empty()) return;
  const GeometryTree tree(geometry);
  for (const GeometryRegion& r : config.geometry.given_regions) {
    const std::string where = fmt::format("{}:{}: region point ({}, {})", r.file, r.line, r.p.x, r.p.y);
    if (!tree.inside(r.p)) throw InputError(where + " lies outside the domain");
    for (const Segment& s : geometry.segments) {
      if (!point_on_segment(r.p, s.a, s.b)) continue;
      throw InputError(fmt::format("{} lies on curve '{}', between two regions; move it inside the region it tags",
                                   where, geometry.curves[static_cast<std::size_t>(s.curve)].name));
    }
    geometry.regions.push_back(r);
  }
}

// geometry.region_names onto the regions of those attributes (over the names a mesh file gave them).
// Throws InputError at the key's line for an attribute that no region of the geometry has.
void name_regions(const CaseConfig& config, Geometry& geometry) {
  for (const CaseConfig::Geometry::RegionName& named : config.geometry.region_names) {
    bool found = false;
    for (GeometryRegion& r : geometry.regions) {
      if (r.attribute != named.attribute) continue;
      r.name = named.name;
      found = true;
    }
    if (found) continue;
    std::set<double> attributes;
    for (const GeometryRegion& r : geometry.regions) attributes.insert(r.attribute);
    throw InputError(fmt::format(
        "{}: geometry.region_names: attribute {} is no region's of the geometry ({})", named.where, named.attribute,
        attributes.empty() ? std::string("it has no regions: a .poly file's regional attributes or a mesh file's "
                                         "regions give them")
                           : fmt::format("its attributes: {}", fmt::join(attributes, ", "))));
  }
}

// The case's geometry into in.geometry: read from the files or the given curves (healed, projected),
// the readers' notes printed, and the far field put around it.
void read_case_geometry(const CaseConfig& config, MeshInputs& in) {
  std::vector<std::string> files;
  for (const std::filesystem::path& f : config.geometry.files) files.push_back(f.string());
  GeometryOptions options;
  options.join_tolerance = config.geometry.join_tolerance;
  options.corner_angle_deg = config.geometry.corner_angle;
  options.hull = config.geometry.hull;
  Equirectangular used;
  const ReadSteps steps{config.geometry.projection, &used, healing_step(config, in), mesh_geometry_files()};
  in.geometry = config.geometry.given_curves.empty()
                    ? read_geometry(files, config.geometry.curve_names, options, steps)
                    : geometry_from_curves(config.geometry.given_curves, config.geometry.curve_names, options,
                                           config.geometry.given_points, steps);
  if (config.geometry.projection == ProjectionKind::Equirectangular) in.projection = used;
  add_given_regions(config, in.geometry);
  name_regions(config, in.geometry);
  // What the readers did beyond the plain reading (a .poly's loops read as subdomains, vertices kept
  // or dropped): always said, also when quiet, since the mesh differs from what the file may suggest.
  const auto say_notes_from = [&](std::size_t first) {
    for (std::size_t k = first; k < in.geometry.notes.size(); ++k)
      fmt::print(stderr, "pdmesh: note: {}\n", in.geometry.notes[k]);
  };
  say_notes_from(0);
  // The far field around everything given: the body becomes a hole; what it leaves out of the body
  // (farfield.cavities) is said in notes after the readers', also when quiet.
  if (config.farfield.given()) {
    const std::size_t said = in.geometry.notes.size();
    in.geometry = with_farfield(in.geometry, config.farfield, config.spacing.gradation, options);
    say_notes_from(said);
  }
}

// Curve names are fields in node and mesh files; one with white space would break them later.
void check_curve_names(const Geometry& geometry) {
  for (std::size_t c = 0; c < geometry.curves.size(); ++c) {
    const std::string& name = geometry.curves[c].name;
    if (name.empty() || name.find_first_of(" \t\r\n") != std::string::npos) {
      throw InputError(
          fmt::format("{}:{}: curve {} name '{}' is empty or contains white space; name the curves "
                      "with geometry.curve_names",
                      geometry.curves[c].file, geometry.curves[c].line, c, name));
    }
  }
}

// For spacing.field = "boundary": what a refusal by the node count appends, where eq. 3.6's q comes
// from (a dense input polyline asks for nodes as fine as its segments everywhere); empty without
// segments.
std::string segment_length_hint(const Geometry& geometry) {
  const auto [shortest, longest] =
      std::minmax_element(geometry.segments.begin(), geometry.segments.end(),
                          [](const Segment& a, const Segment& b) { return a.length < b.length; });
  if (shortest == geometry.segments.end()) return {};
  return fmt::format(
      " (eq. 3.6 takes q from the lengths of the input's {} segments, {:.3g} to {:.3g}: a "
      "coarser polyline, spacing.scale or spacing.expression asks for fewer)",
      geometry.segments.size(), shortest->length, longest->length);
}

// The line about a metric field or a spacing field read from a file, with the time since `start`;
// empty for the other fields.
std::string spacing_summary_line(const CaseConfig& config, const MeshInputs& in,
                                 std::chrono::steady_clock::time_point start) {
  std::string summary;
  if (in.metric) {
    summary = fmt::format(
        "spacing: the metric field ({}) built in {:.3f} s; the nodes start at unit metric length, "
        "relax in the metric and are triangulated in it (docs/metric-fields.md)",
        config.spacing.field == SpacingKind::Hessian ? "hessian" : "metric",
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  }
  const SpacingField* base = in.spacing.get();
  if (const auto* r = dynamic_cast<const RegionSpacing*>(base)) base = &r->base();
  if (const auto* m = dynamic_cast<const MeshSpacing*>(base)) {
    const MeshFieldData& d = m->data();
    const auto [lo, hi] = std::minmax_element(d.q.begin(), d.q.end());
    summary = fmt::format(
        "spacing: '{}' on {} ({} triangles, {} points, q from {:.4g} to {:.4g}), read, checked and "
        "indexed in {:.3f} s",
        d.array, d.file, d.triangles.size(), d.points.size(), *lo, *hi,
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  }
  return summary;
}

// geometry.curves = "smooth": the dense polyline of the smooth curves and its tree, or the reason
// the polylines are meshed instead (in.smooth_fallback).
void build_smooth_curves(const CaseConfig& config, MeshInputs& in) {
  if (config.geometry.curves == CurveKind::Smooth) {
    DenseOptions dense_options;
    dense_options.join_tolerance = config.geometry.join_tolerance;
    try {
      // Constraints are smoothed too, their meeting points kept on the smooth curves
      // (geometry/smooth_embedded.hpp); without them this is make_dense_geometry.
      in.dense = std::make_unique<DenseGeometry>(make_dense_embedded(
          in.geometry, config.geometry.corner_angle, [&](Vec2 p) { return in.spacing->at(p); }, dense_options));
    } catch (const GeometryError& e) {
      // Smooth curves through coarse points can cross where the polylines pass close to each other.
      in.smooth_fallback = e.what();
    }
    if (in.dense) {
      check_coordinate_resolution(in.dense->geometry, *in.spacing);
      in.dense_tree = std::make_unique<GeometryTree>(in.dense->geometry);
    }
  }
}

}  // namespace

MeshInputs::MeshInputs(const CaseConfig& config) {
  read_case_geometry(config, *this);
  check_curve_names(geometry);
  // Checked here, before the run, so that a misspelt name writes nothing.
  curves_by_name(geometry, config.output.open_boundaries, config.source.string() + ": output.open_boundaries");
  curves_by_name(geometry, config.output.walls, config.source.string() + ": output.walls");
  // The geometry's quadtree and the queries' per-segment arrays, before they are made (the
  // geometry itself is read: its size was the file's).
  check_memory(
      config.max_memory, GeometryTree::kBytesPerSegment * static_cast<double>(geometry.segments.size()),
      fmt::format("{}: the geometry's quadtree over {} segments", config.source.string(), geometry.segments.size()),
      "raise --max-memory");
  tree = std::make_unique<GeometryTree>(geometry);
  spacing_options = pdmesh::spacing_options(config);
  check_spacing_options(spacing_options);
  if (config.spacing.field == SpacingKind::Boundary) node_hint = segment_length_hint(geometry);
  const auto spacing_start = std::chrono::steady_clock::now();
  metric = make_case_metric(config, *tree);
  spacing = make_case_spacing(config, *tree, metric.get());
  // Fixed nodes at both ends of a boundary arc much shorter than the field there: the field follows
  // the arc (spacing/short_arcs.hpp). Only where the field places the boundary nodes and spreads
  // sources (gradation): the thesis' field stays eq. 3.6 exactly.
  if (!metric && config.boundary.nodes == BoundaryNodeRule::Spacing && spacing_options.gradation > 0.0)
    for (const PointSource& s : short_arc_sources(geometry, *spacing, config.spacing.scale))
      spacing_options.points.push_back(s);
  spacing_summary = spacing_summary_line(config, *this, spacing_start);
  // Before anything else uses them: with unresolvable coordinates the node estimate's tree could
  // refine without end.
  check_coordinate_resolution(geometry, *spacing);
  boundary_rule = config.boundary.nodes;
  build_smooth_curves(config, *this);
}

BoundaryPlacement place_boundary(const CaseConfig& config, const MeshInputs& inputs, const SpacingStage& spacing) {
  BoundaryPlacement placed;
  // The thesis' rule (every point of the input polyline) is applied by the initialization itself.
  if (!inputs.dense && inputs.boundary_rule == BoundaryNodeRule::Input) return placed;
  const Geometry& on = inputs.node_geometry();
  PlacementOptions placement;
  placement.max_nodes = config.max_nodes;
  // Placed by the final field (the pipeline's: graded, feature size, curvature), so that the boundary
  // rows match the interior rows next to them.
  const SpacingField& q = spacing.field();
  const CurveStations stations = inputs.boundary_rule == BoundaryNodeRule::Spacing
                                     ? spacing_stations(on, q, placement)
                                     : vertex_stations(on, &inputs.dense->vertex);
  placed.nodes = assemble_boundary_nodes(on, q, stations);
  placed.resolution = station_resolution(on, stations);
  return placed;
}

double relax_scale(const CaseConfig& config) {
  // A metric run relaxes in the metric (sigma = 1 there), which this scale does not reach: its
  // isotropic size stays as asked.
  return config.spacing.metric() ? 1.0 : config.spacing.relax_scale;
}

SpacingOptions spacing_options(const CaseConfig& config) {
  SpacingOptions o;
  // The field the nodes follow; SpacingStage::asked() divides relax_scale out again for the reports.
  o.scale = config.spacing.scale * relax_scale(config);
  o.gradation = config.spacing.gradation;
  o.rows_in_gap = config.spacing.rows_in_gap;
  o.curvature_angle = config.spacing.curvature_angle;
  o.background.tolerance = config.spacing.background_tolerance;
  // A cap above the default (the best preset's q/2) is for eq. 3.6's jumps, which only the boundary field
  // has: a given field (an expression, a mesh's sizes: pdmesh smooth keeps them) is sampled at least as
  // finely as the default (docs/spacing.md, "The best preset's interior cap").
  o.background.min_side_fraction =
      config.spacing.field == SpacingKind::Boundary
          ? config.spacing.background_min_side
          : std::min(config.spacing.background_min_side, BackgroundOptions{}.min_side_fraction);
  o.background.boundary_min_side_fraction = config.spacing.background_boundary_min_side;
  // The budgets the quadtree is built within (a field that asks for 1e9 nodes is refused on a coarse
  // level, before the tree at its resolution exists).
  o.background.max_nodes = static_cast<double>(config.max_nodes);
  o.background.memory = config.max_memory;
  // The sources' floor stays with boundary nodes placed by the field too: without it the feature size
  // asks for q -> 0 toward sharp V tips, whose placed nodes then crowd into slivers (measured on the
  // corpus: heatsink_channel 0.22 deg, coastline 0.47 deg without; docs/spacing.md). The final floor
  // only serves input points as boundary nodes: placed nodes follow whatever finer field the case asks.
  o.input_boundary_floor = kInputBoundaryFloor;
  o.final_floor = config.boundary.nodes == BoundaryNodeRule::Input;
  return o;
}

namespace {

bool refused_by_nodes(const LimitError& e) {
  return std::string_view(e.what()).find("--max-nodes") != std::string_view::npos;
}

// The hexagonal-packing estimate against --max-nodes (`source` prefixes the message unless empty).
void refuse_above_limit(const std::string& source, std::uint64_t max_nodes, double estimate, const char* which) {
  if (!(estimate <= static_cast<double>(max_nodes))) {
    throw LimitError(fmt::format(
        "{}the {} asks for about {} nodes (hexagonal-packing estimate), "
        "more than --max-nodes {}; coarsen the spacing or raise --max-nodes",
        source.empty() ? std::string() : source + ": ", which,
        std::isfinite(estimate) ? fmt::format("{:.0f}", estimate) : std::string("infinitely many"), max_nodes));
  }
}

}  // namespace

SpacingStage::SpacingStage(const CaseConfig& config, const MeshInputs& inputs, Build build)
    : source_(config.source.string()), node_hint_(inputs.node_hint), metric_(inputs.metric.get()) {
  const std::uint64_t max_nodes = config.max_nodes;
  // The base field's quadtree is checked before the limits refine it (they only lower q).
  const auto check_base = [&inputs, max_nodes](const BackgroundSpacing& base_tree) {
    // Only the refusal matters here (the final field's estimate is the one reported): where the
    // bound, every leaf not outside counted whole, is clearly below the limit, the estimate is too
    // (it is not above the bound but for rounding, ~1e-13 relative), and its boundary leaves' geometry
    // queries (0.04 s on 30P30N's curves alone) are skipped.
    const double bound = node_count_bound(base_tree);
    if (std::isfinite(bound) && bound * (1.0 + 1e-6) <= static_cast<double>(max_nodes)) return;
    refuse_above_limit("", max_nodes, estimate_node_count(*inputs.tree, base_tree), "spacing field before its limits");
  };
  const SpacingOptions& options = inputs.spacing_options;
  try {
    pipeline_ = std::make_unique<SpacingPipeline>(*inputs.spacing, *inputs.tree, options,
                                                  options.modifies() ? check_base : SpacingPipeline::BaseCheck{});
  } catch (const LimitError& e) {
    throw LimitError(fmt::format("{}: {}{}", source_, e.what(), refused_by_nodes(e) ? node_hint_ : ""));
  }
  // The sources lower q: the final field must be resolvable too.
  if (!pipeline_->exact()) check_coordinate_resolution(inputs.geometry, pipeline_->field());
  relax_scale_ = pdmesh::relax_scale(config);
  if (relax_scale_ != 1.0) asked_ = std::make_unique<ScaledSpacing>(pipeline_->field(), 1.0 / relax_scale_);
  if (build == Build::Meshing) (void)background();
}

const BackgroundSpacing& SpacingStage::background() const {
  // The thesis' field builds its quadtree (the node estimate's and the simulation's lookup table) on
  // first use, within the same budgets.
  try {
    return pipeline_->background();
  } catch (const LimitError& e) {
    throw LimitError(fmt::format("{}: {}{}", source_, e.what(), refused_by_nodes(e) ? node_hint_ : ""));
  }
}

std::vector<std::string> MeshInputs::curve_names() const {
  std::vector<std::string> names;
  for (const Curve& c : geometry.curves) names.push_back(c.name);
  return names;
}

double check_node_limit(const CaseConfig& config, const MeshInputs& inputs, const SpacingStage& spacing) {
  // One pass over the leaves of the final field's quadtree (init/node_estimate), which the simulation
  // samples anyway: per-sample queries over the initialization tree took longer than the simulation
  // on rods_fine (7.4 s against 5.5 s, thesis preset).
  const BackgroundSpacing& background = spacing.background();
  const double estimate = estimate_node_count(inputs.node_tree(), background);
  refuse_above_limit(config.source.string(), config.max_nodes, estimate, "spacing field");
  if (config.init.total > config.max_nodes) {
    throw LimitError(fmt::format("{}: init.total = {} is more than --max-nodes {}", config.source.string(),
                                 config.init.total, config.max_nodes));
  }
  // The stages after this one (the fill, the simulation, the triangulation, the cleanup, the writers)
  // each hold arrays in proportion to the node count: the run's peak, before the first of them.
  const double nodes = std::max(estimate, static_cast<double>(config.init.total));
  check_memory(
      config.max_memory, run_memory_bytes(nodes, background.stats().bytes),
      fmt::format("{}: meshing about {:.0f} nodes (hexagonal-packing estimate)", config.source.string(), nodes),
      "raise --max-memory, coarsen the spacing or lower --max-nodes");
  return estimate;
}

double run_memory_bytes(double nodes, std::size_t field_bytes) {
  return kRunBytesBase + kRunBytesPerNode * kRunNodeGrowth * nodes + static_cast<double>(field_bytes);
}

InitialDistribution make_metric_initial(const CaseConfig& config, const MeshInputs& inputs,
                                        const SpacingStage& spacing) {
  // Boundary stations at unit metric length along each curve (placed by the curve's tangent length in
  // the metric, with the validity rule measured by it too), then the interior fill in the metric.
  const Geometry& on = inputs.node_geometry();
  const GeometryTree& tree = inputs.node_tree();
  PlacementOptions placement;
  placement.max_nodes = config.max_nodes;
  const CurveMetricSpacing along(tree, *inputs.metric);
  InitialDistribution initial;
  initial.nodes = assemble_boundary_nodes(on, spacing.field(), spacing_stations(on, along, placement));
  MetricFillOptions fill;
  fill.max_nodes = config.max_nodes;
  if (config.init.file.empty()) {
    initial.tree_nodes = metric_fill(tree, *inputs.metric, spacing.field(), initial.nodes, fill);
  } else {
    initial.tree_nodes =
        warm_fill(tree, inputs.metric.get(), spacing.field(), initial.nodes, read_warm_points(config.init.file), fill);
    fill.grow_from_interior = true;
    initial.tree_nodes += metric_fill(tree, *inputs.metric, spacing.field(), initial.nodes, fill);
  }
  initial.estimate = NAN;
  return initial;
}

namespace {

// The warm start of an isotropic run: the boundary nodes as the case places them (by the field, or the
// input's points), then the file's interior points, spaced by q (warm_fill with no metric).
InitialDistribution make_warm_initial(const CaseConfig& config, const MeshInputs& inputs, const SpacingStage& spacing) {
  const BoundaryPlacement boundary = place_boundary(config, inputs, spacing);
  InitialDistribution initial;
  initial.nodes = boundary.nodes ? *boundary.nodes : make_boundary_nodes(inputs.node_geometry(), spacing.field());
  MetricFillOptions fill;
  fill.max_nodes = config.max_nodes;
  initial.tree_nodes =
      warm_fill(inputs.node_tree(), nullptr, spacing.field(), initial.nodes, read_warm_points(config.init.file), fill);
  initial.estimate = NAN;
  return initial;
}

}  // namespace

InitialDistribution make_initial(const CaseConfig& config, const MeshInputs& inputs, const SpacingStage& spacing) {
  // run_mesh and the Python Mesher mesh a layered case's core (a case without the tables, from
  // build_layers); a caller driving the stages with the tables would mesh the whole domain without them.
  if (!config.boundary_layers.empty())
    throw InputError(fmt::format("{}: [[boundary_layer]]: the stages mesh the core's case (build_layers), not this one",
                                 config.source.string()));
  if (inputs.metric) return make_metric_initial(config, inputs, spacing);
  if (config.init.kept) {
    InitialDistribution initial;
    initial.nodes = kept_node_set(*config.init.kept, inputs.node_geometry(), spacing.field());
    initial.estimate = NAN;
    return initial;
  }
  if (!config.init.file.empty()) return make_warm_initial(config, inputs, spacing);
  const BoundaryPlacement boundary = place_boundary(config, inputs, spacing);
  InitOptions options;
  options.method = config.init.method;
  options.seed = config.init.seed;
  options.density = config.init.density;
  options.density_where = config.init.density_where;
  options.lattice_levels = config.init.lattice_levels;
  options.hybrid_spread = config.init.hybrid_spread;
  if (config.init.total > 0) options.total = static_cast<std::size_t>(config.init.total);
  options.with_estimate = false;  // check_node_limit computed it just before
  options.boundary = boundary.nodes ? &*boundary.nodes : nullptr;
  options.segment_resolution = boundary.resolution.empty() ? nullptr : &boundary.resolution;
  return make_initial_distribution(inputs.node_tree(), spacing.field(), options);
}

}  // namespace pdmesh
