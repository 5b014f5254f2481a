// The case's spacing field: eq. 3.6, a uniform size, an expression, a background mesh read from a file,
// or the isotropic size of a metric field, lowered by the refinement regions; and the metric field itself.
#include "app/config/case_spacing.hpp"

#include <algorithm>
#include <cctype>
#include <fmt/format.h>
#include <fmt/ranges.h>

#include "core/errors.hpp"
#include "core/input_file.hpp"
#include "io/medit_reader.hpp"
#include "io/metric_mesh_file.hpp"
#include "io/spacing_mesh_file.hpp"
#include "spacing/background_field.hpp"
#include "spacing/fixed_point_metric.hpp"
#include "spacing/hessian_metric.hpp"
#include "spacing/mesh_spacing.hpp"
#include "spacing/refine_regions.hpp"
#include "spacing/metric_gradation.hpp"
#include "spacing/metric_size_field.hpp"

namespace pdmesh {

namespace {

std::unique_ptr<SpacingField> base_spacing(const CaseConfig& config, const GeometryTree& tree,
                                           const MetricField* metric) {
  // A caller's field (the Python API's size callable) is sampled once, in batches (at_many), into a
  // background field, so that nothing later evaluates it per point.
  if (config.spacing.given) return std::make_unique<BackgroundSpacing>(*config.spacing.given, tree);
  switch (config.spacing.field) {
    case SpacingKind::Expression:
      return std::make_unique<ExpressionSpacing>(config.spacing.expression);
    case SpacingKind::Mesh: {
      auto field = load_mesh_spacing(config.spacing.file, config.spacing.array);
      field->check_covers(tree.geometry());
      return field;
    }
    case SpacingKind::Metric:
    case SpacingKind::Hessian:
      if (metric == nullptr) throw InputError("a metric spacing field needs its metric (make_case_metric)");
      return std::make_unique<MetricSizeField>(*metric);
    case SpacingKind::Boundary:
      break;
  }
  if (config.spacing.size > 0.0) return std::make_unique<UniformSpacing>(config.spacing.size);
  return std::make_unique<BoundarySpacing>(tree);
}

}  // namespace

std::unique_ptr<SpacingField> make_case_spacing(const CaseConfig& config, const GeometryTree& tree,
                                                const MetricField* metric) {
  std::unique_ptr<SpacingField> base = base_spacing(config, tree, metric);
  // Refinement regions lower the base field inside them; the pipeline's sources and gradation apply
  // after. A .poly file's maximum areas size their subdomains (not under a metric, which sets the sizes).
  std::vector<RefineRegion> regions = config.spacing.regions;
  if (!config.spacing.metric()) {
    for (RefineRegion& r : max_area_regions(tree.geometry().regions)) regions.push_back(std::move(r));
  }
  if (regions.empty()) return base;
  return std::make_unique<RegionSpacing>(std::move(base), std::move(regions), &tree.geometry());
}

namespace {

bool is_medit(const std::filesystem::path& file) {
  const std::string ext = lower_extension(file);
  return ext == ".mesh";
}

// spacing.metric_gradation along the background mesh's edges, then the field of the data.
std::unique_ptr<MetricField> mesh_field(const CaseConfig& config, MetricMeshData data) {
  if (config.spacing.metric_gradation > 0.0) {
    MetricGradationOptions options;
    options.beta = config.spacing.metric_gradation;
    limit_metric_gradation(data.points, triangle_edges(data.triangles), data.metrics, options);
  }
  return make_mesh_metric_field(std::move(data));
}

// The cells per side of the grid over the geometry's extents on which a metric given by expressions is
// sampled for spacing.metric_gradation: the grid's metric, interpolated log-Euclidean, replaces the
// expressions. As fine as the data of issue 37's tanh layer (1024 x 1024).
constexpr int kGradationGrid = 1024;

// With spacing.metric_gradation, a metric given by expressions (`field`) sampled on a grid over the
// extents, graded along the grid's edges; otherwise `field` itself.
std::unique_ptr<MetricField> graded(const CaseConfig& config, const GeometryTree& tree,
                                    std::unique_ptr<MetricField> field, std::string what) {
  if (!(config.spacing.metric_gradation > 0.0)) return field;
  MetricMeshData data;
  sample_metric_grid(*field, tree.geometry().extents, kGradationGrid, data.points, data.triangles, data.metrics);
  data.what = std::move(what);
  return mesh_field(config, std::move(data));
}

// The case's metric field as its keys give it.
std::unique_ptr<MetricField> case_metric_field(const CaseConfig& config, const GeometryTree& tree) {
  const auto& s = config.spacing;
  if (s.field == SpacingKind::Metric) {
    if (!s.file.empty()) {
      return mesh_field(config,
                        is_medit(s.file) ? load_medit_metric(s.file, s.sol) : load_metric_mesh(s.file, s.array));
    }
    if (!s.m11.empty()) {
      return graded(
          config, tree,
          std::make_unique<ExpressionMetricField>(ExpressionMetricField::Form::components, s.m11, s.m12, s.m22),
          "the metric of spacing.m11, m12, m22 on a grid");
    }
    return graded(config, tree,
                  std::make_unique<ExpressionMetricField>(ExpressionMetricField::Form::sizes, s.h1, s.h2, s.angle),
                  "the metric of spacing.h1, h2, angle on a grid");
  }
  if (s.field != SpacingKind::Hessian) return nullptr;
  HessianMetricOptions options;
  options.complexity = s.complexity;
  options.hmin = s.hmin;
  options.hmax = s.hmax;
  options.max_anisotropy = s.max_anisotropy;
  options.p = s.norm;
  if (s.file.empty()) {
    // The Hessian by central differences of a step of spacing.hessian_step times the geometry's extent
    // (default 1e-5: the function's own curvature, rounding noise ~1e-16 |u| / step² far below it),
    // and D by the midpoint rule on a 1024 x 1024 grid over the extents (as tools/eval's metric.py).
    // A step of 2/1024 sees u's curvature at the scale a fit to data on that grid sees; at the
    // inflection of a curved layer the exact Hessian's second eigenvalue vanishes and the metric
    // thins the node density there (docs/metric-fields.md, "Hessians and the L^p-optimal metric").
    const Box box = tree.geometry().extents;
    const double extent = std::max(box.hi.x - box.lo.x, box.hi.y - box.lo.y);
    return graded(config, tree,
                  std::make_unique<HessianMetricField>(s.function, box, options, s.hessian_step * extent, 1024),
                  "the hessian metric of spacing.function on a grid");
  }
  ScalarMeshData data = load_scalar_mesh(s.file, s.array);
  MetricMeshData metric;
  if (s.arrays.size() > 1) {
    std::vector<std::vector<double>> values{std::move(data.values)};
    std::vector<std::string> what{data.what};
    for (std::size_t k = 1; k < s.arrays.size(); ++k) {
      ScalarMeshData more = load_scalar_mesh(s.file, s.arrays[k]);
      values.push_back(std::move(more.values));
      what.push_back(std::move(more.what));
    }
    metric.metrics = intersected_hessian_metrics_on_mesh(data.points, data.triangles, values, options, what);
    data.what = fmt::format("{} (intersected)", fmt::join(what, ", "));
  } else {
    metric.metrics = hessian_metrics_on_mesh(data.points, data.triangles, data.values, options, data.what);
  }
  metric.points = std::move(data.points);
  metric.triangles = std::move(data.triangles);
  metric.what = data.what;
  return mesh_field(config, std::move(metric));
}

}  // namespace

std::unique_ptr<MetricField> make_case_metric(const CaseConfig& config, const GeometryTree& tree) {
  std::unique_ptr<MetricField> field = case_metric_field(config, tree);
  if (!field) return nullptr;
  // A fixed node samples the field at one place for the whole run: its metric is graded from the
  // field around it, so that a place singular in the field (a Hessian metric's inflection line
  // through a leading edge) does not size every pair and edge at the node (spacing/fixed_point_metric).
  const double beta = config.spacing.metric_gradation > 0.0 ? config.spacing.metric_gradation : kFixedPointGradation;
  return with_fixed_point_metrics(std::move(field), tree, beta);
}

}  // namespace pdmesh
