// The case's spacing field: eq. 3.6, an expression, or a background mesh read from a file.
#include "app/config/case_spacing.hpp"

#include "spacing/background_field.hpp"
#include "io/spacing_mesh_file.hpp"
#include "spacing/mesh_spacing.hpp"

namespace pdmesh {

std::unique_ptr<SpacingField> make_case_spacing(const CaseConfig& config, const GeometryTree& tree) {
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
    case SpacingKind::Boundary:
      break;
  }
  return std::make_unique<BoundarySpacing>(tree);
}

}  // namespace pdmesh
