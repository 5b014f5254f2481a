// The spacing field a case asks for (the [spacing] section), built in one place for `pdmesh mesh`,
// `pdmesh quality --geometry` and `pdmesh bench`.
#pragma once
#include <memory>

#include "app/config/case_file.hpp"
#include "geometry/geometry_tree.hpp"
#include "spacing/spacing_field.hpp"

namespace pdmesh {

// spacing.field: "boundary" (thesis eq. 3.6 on the tree's geometry; refers to `tree`, which must
// outlive the field), "expression" (muParser) or "mesh" (spacing.file's point data spacing.array,
// checked to cover every point of the geometry). Throws InputError on bad expressions and bad files.
// A field given by the caller (config.spacing.given, the Python API) replaces all of these: it is
// sampled once into a BackgroundSpacing.
std::unique_ptr<SpacingField> make_case_spacing(const CaseConfig& config, const GeometryTree& tree);

}  // namespace pdmesh
