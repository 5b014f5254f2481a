// The spacing field a case asks for (the [spacing] section), built in one place for `pdmesh mesh`,
// `pdmesh quality --geometry` and `pdmesh bench`.
#pragma once
#include <memory>

#include "app/config/case_file.hpp"
#include "geometry/geometry_tree.hpp"
#include "spacing/metric_field.hpp"
#include "spacing/spacing_field.hpp"

namespace pdmesh {

// spacing.field: "boundary" (thesis eq. 3.6 on the tree's geometry; refers to `tree`, which must
// outlive the field), "expression" (muParser) or "mesh" (spacing.file's point data spacing.array,
// checked to cover every point of the geometry). Throws InputError on bad expressions and bad files.
// A field given by the caller (config.spacing.given, the Python API) replaces all of these: it is
// sampled once into a BackgroundSpacing.
// spacing.field "metric" or "hessian": the isotropic q derived from `metric` (MetricSizeField, which
// refers to it), which must then be the field make_case_metric built. spacing.size replaces eq. 3.6 by
// that size everywhere; [[refine]] regions (spacing.regions) then lower the field inside them
// (RegionSpacing, spacing/refine_regions.hpp).
std::unique_ptr<SpacingField> make_case_spacing(const CaseConfig& config, const GeometryTree& tree,
                                                const MetricField* metric = nullptr);

// The metric field of spacing.field = "metric" (expressions, a .vtu/.msh with a 3-component array, or a
// Medit .mesh + .sol) or "hessian" (the L2-optimal metric of spacing.function, or of the scalar data
// spacing.array on spacing.file, over the geometry's extents), with spacing.metric_gradation applied
// along the background mesh's edges (expressions and functions: sampled on a grid over the extents
// first), and at the tree's fixed points where the field is not continuous its value graded from the
// field around them (with_fixed_point_metrics, at spacing.metric_gradation or kFixedPointGradation);
// null for the isotropic fields. Throws InputError naming the file, key or expression and the value.
std::unique_ptr<MetricField> make_case_metric(const CaseConfig& config, const GeometryTree& tree);

}  // namespace pdmesh
