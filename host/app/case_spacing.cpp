// The case's spacing field: eq. 3.6, an expression, or a background mesh read from a file.
#include "app/case_spacing.hpp"

#include "spacing/mesh_spacing.hpp"

namespace pdmesh {

std::unique_ptr<SpacingField> make_case_spacing(const CaseConfig& config, const GeometryTree& tree) {
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
