// [[periodic]]: the tables checked against the geometry, the source curves' nodes placed and
// transformed, and the case the later stages mesh, on those nodes as fixed points.
#include "app/pipeline/periodic_pipeline.hpp"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <fmt/ranges.h>

#include "app/pipeline/pipeline_detail.hpp"
#include "core/errors.hpp"
#include "core/input_file.hpp"
#include "init/boundary_placement.hpp"
#include "init/metric_fill.hpp"

namespace pdmesh {

namespace {

// The transform maps the source onto the image within this share of the geometry's diagonal.
constexpr double kMatchTolerance = 1e-6;

// The smaller of q at a point and at its image: the source's nodes are placed by it, so that the
// image's nodes (their transforms) are not coarser than the field asks there either.
class PairedSpacing final : public SpacingField {
 public:
  PairedSpacing(const SpacingField& q, const PeriodicTransform& t) : q_(q), t_(t) {}
  double at(Vec2 p) const override { return std::min(q_.at(p), q_.at(t_.apply(p))); }

 private:
  const SpacingField& q_;
  PeriodicTransform t_;
};

// The case's metric by reference for the core (which outlives it, as the field above): the core's
// stages run in the metric the source's stations were placed by.
class MetricReference final : public MetricField {
 public:
  explicit MetricReference(const MetricField& m) : m_(m) {}
  Metric at(Vec2 p) const override { return m_.at(p); }

 private:
  const MetricField& m_;
};

// A field by reference: the case's, which outlives the core's stages (build_periodic's contract).
class FieldReference final : public SpacingField {
 public:
  explicit FieldReference(const SpacingField& q) : q_(q) {}
  double at(Vec2 p) const override { return q_.at(p); }
  void at_many(const std::vector<Vec2>& p, std::vector<double>& q) const override { q_.at_many(p, q); }

 private:
  const SpacingField& q_;
};

std::string describe(const PeriodicTransform& t) {
  if (t.is_rotation())
    return fmt::format("the rotation by {:.12g} deg about ({}, {})", t.angle_rad * 180.0 / M_PI, t.center.x,
                       t.center.y);
  return fmt::format("the translation ({}, {})", t.shift.x, t.shift.y);
}

int curve_index(const Geometry& g, const CaseConfig::Periodic& p, const std::string& name) {
  for (std::size_t c = 0; c < g.curves.size(); ++c)
    if (g.curves[c].name == name) {
      if (g.curves[c].constraint)
        throw InputError(
            fmt::format("{}: [[periodic]] curves = [\"{}\", \"{}\"]: '{}' is an embedded constraint, not a "
                        "boundary curve",
                        p.where, quote_input(p.source), quote_input(p.image), quote_input(name)));
      return static_cast<int>(c);
    }
  std::vector<std::string> names;
  for (const Curve& c : g.curves) names.push_back(c.name);
  throw InputError(fmt::format("{}: [[periodic]] curves = [\"{}\", \"{}\"]: unknown curve '{}' (the curves: {})",
                               p.where, quote_input(p.source), quote_input(p.image), quote_input(name),
                               fmt::join(names, ", ")));
}

}  // namespace

ResolvedPeriodic resolve_periodic(const CaseConfig::Periodic& p, const Geometry& on) {
  const double diagonal = std::hypot(on.extents.hi.x - on.extents.lo.x, on.extents.hi.y - on.extents.lo.y);
  const double tolerance = kMatchTolerance * diagonal;
  ResolvedPeriodic r;
  r.tolerance = tolerance;
  r.source = curve_index(on, p, p.source);
  r.image = curve_index(on, p, p.image);
  const Curve& source = on.curves[static_cast<std::size_t>(r.source)];
  const Curve& image = on.curves[static_cast<std::size_t>(r.image)];
  switch (p.kind) {
    case CaseConfig::Periodic::Kind::Translate:
      r.transform = PeriodicTransform::translation({p.translate[0], p.translate[1]});
      break;
    case CaseConfig::Periodic::Kind::Rotate:
      r.transform = PeriodicTransform::rotation({p.center[0], p.center[1]}, p.angle_deg);
      break;
    case CaseConfig::Periodic::Kind::Infer:
      r.transform = PeriodicTransform::translation(inferred_translation(source, image));
      break;
  }
  const PeriodicMiss miss = periodic_miss(source, image, r.transform);
  if (!(miss.distance <= tolerance))
    throw InputError(fmt::format(
        "{}: [[periodic]] curves = [\"{}\", \"{}\"]: {} does not map '{}' onto '{}': they are {:.6g} apart at "
        "({:.9g}, {:.9g}), above the tolerance {:.3g} (1e-6 of the geometry's diagonal)",
        p.where, quote_input(p.source), quote_input(p.image), describe(r.transform), quote_input(p.source),
        quote_input(p.image), miss.distance, miss.at.x, miss.at.y, tolerance));
  r.miss = miss.distance;
  return r;
}

void check_periodic(const CaseConfig& config, const MeshInputs& inputs) {
  check_periodic_case(config);
  for (const CaseConfig::Periodic& p : config.periodic) (void)resolve_periodic(p, inputs.node_geometry());
}

void check_periodic_case(const CaseConfig& config) {
  if (config.periodic.empty()) return;
  const std::string& where = config.periodic.front().where;
  for (const CaseConfig::Periodic& p : config.periodic)
    for (const CaseConfig::BoundaryLayer& b : config.boundary_layers)
      for (const std::string& name : {p.source, p.image})
        if (std::find(b.curves.begin(), b.curves.end(), name) != b.curves.end())
          throw InputError(
              fmt::format("{}: [[periodic]]: curve '{}' is also a boundary-layer wall ({}); a periodic "
                          "curve cannot carry layers",
                          p.where, quote_input(name), b.curves_where));
  if (config.motion.enabled) throw InputError(fmt::format("{}: [[periodic]] is not supported with [motion]", where));
  if (config.resume) throw InputError(fmt::format("{}: --resume is not supported with [[periodic]]", where));
  if (config.init.kept || !config.init.file.empty())
    throw InputError(
        fmt::format("{}: [[periodic]] is not supported with a warm start (init.file, pdmesh smooth)", where));
}

std::unique_ptr<PeriodicCase> build_periodic(const CaseConfig& config, const MeshInputs& inputs,
                                             const SpacingStage& spacing) {
  check_periodic_case(config);
  const Geometry& on = inputs.node_geometry();
  auto out = std::make_unique<PeriodicCase>();
  std::vector<RawCurve> curves;
  for (const Curve& c : on.curves) {
    RawCurve r{c.name, c.points, c.file, c.line, {}, c.fixed_points};
    r.constraint = c.constraint;
    curves.push_back(std::move(r));
  }
  // The source's stations: by the field (the smaller of q here and at the image), or the input's
  // points under boundary.nodes = "input" (the thesis' rule).
  PlacementOptions placement;
  placement.max_nodes = config.max_nodes;
  for (const CaseConfig::Periodic& p : config.periodic) {
    const ResolvedPeriodic resolved = resolve_periodic(p, on);
    const int s = resolved.source, i = resolved.image;
    const Curve& source = on.curves[static_cast<std::size_t>(s)];
    const Curve& image = on.curves[static_cast<std::size_t>(i)];
    const PeriodicTransform& t = resolved.transform;
    std::vector<Vec2> nodes;
    if (inputs.metric) {
      // A metric run's stations are unit metric lengths apart along the curve (make_metric_initial):
      // here the shorter of the unit step at a point and at its image, along the curve there.
      const CurveMetricSpacing along(inputs.node_tree(), *inputs.metric);
      const PairedSpacing paired(along, t);
      const CurveStations stations = spacing_stations(on, paired, placement);
      for (const BoundaryStation& st : stations[static_cast<std::size_t>(s)]) nodes.push_back(st.p);
    } else if (inputs.dense || inputs.boundary_rule == BoundaryNodeRule::Spacing) {
      const PairedSpacing paired(spacing.field(), t);
      const CurveStations stations = inputs.boundary_rule == BoundaryNodeRule::Spacing
                                         ? spacing_stations(on, paired, placement)
                                         : vertex_stations(on, &inputs.dense->vertex);
      for (const BoundaryStation& st : stations[static_cast<std::size_t>(s)]) nodes.push_back(st.p);
    } else {
      nodes = source.points;
    }
    const bool reversed = periodic_reversed(source, image, t);
    PeriodicNodes pair;
    pair.source_curve = s;
    pair.image_curve = i;
    pair.transform = t;
    pair.source = nodes;
    for (const Vec2& q : nodes) pair.image.push_back(t.apply(q));
    // The image keeps its own ends, which it shares with its neighbouring curves (their transforms
    // differ from them by rounding at most: within the tolerance checked above).
    pair.image.front() = reversed ? image.points.back() : image.points.front();
    pair.image.back() = reversed ? image.points.front() : image.points.back();
    curves[static_cast<std::size_t>(s)].points = pair.source;
    curves[static_cast<std::size_t>(s)].fixed_points = true;
    std::vector<Vec2> image_points = pair.image;
    if (reversed) std::reverse(image_points.begin(), image_points.end());
    curves[static_cast<std::size_t>(i)].points = std::move(image_points);
    curves[static_cast<std::size_t>(i)].fixed_points = true;
    out->notes.push_back(fmt::format(
        "periodic: '{}' -> '{}' by {}{}, {} node pairs (largest miss of the curves {:.3g})", p.source, p.image,
        describe(t),
        p.kind == CaseConfig::Periodic::Kind::Infer || p.inferred ? " (inferred from the curves' ends)" : "",
        nodes.size(), resolved.miss));
    out->pairs.push_back(std::move(pair));
  }
  // The core: the node geometry's polylines (dense for smooth curves, healed already) and its embedded
  // points, the case's field as asked its base field, as with [[boundary_layer]].
  out->core =
      mesh_detail::core_case_on_curves(config, std::move(curves), std::make_shared<FieldReference>(spacing.asked()));
  out->core.periodic.clear();
  out->core.geometry.given_points = on.embedded_points;
  out->core.geometry.heal = false;
  return out;
}

std::unique_ptr<MeshInputs> periodic_core_inputs(const PeriodicCase& periodic, const MeshInputs& inputs) {
  auto core = std::make_unique<MeshInputs>(periodic.core);
  core->projection = inputs.projection;
  core->geometry.regions = inputs.geometry.regions;
  core->periodic = periodic.pairs;
  // A metric run: the core's metric is the case's (with layers the layered core's, graded to the fronts),
  // the one the source's stations were placed by.
  if (inputs.metric) core->metric = std::make_unique<MetricReference>(*inputs.metric);
  return core;
}

}  // namespace pdmesh
