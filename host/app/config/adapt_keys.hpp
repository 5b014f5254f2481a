// The case keys of `pdmesh adapt` (app/cli/adapt_command.hpp) and of pdmesh.adapt in Python: the
// case's [spacing] table replaced by the Hessian metric of a solution (docs/metric-fields.md,
// "Adaptation to a solution").
#pragma once
#include <optional>
#include <string>
#include <vector>

#include "app/config/case_file.hpp"

namespace pdmesh {

struct AdaptOptions {
  std::string solution;             // SOL: a .vtu or .msh with point data
  std::vector<std::string> arrays;  // --array: one or more of SOL's point arrays
  // The metric's keys as the user wrote them (TOML values; the case validator checks them and names
  // the option in its messages).
  std::string complexity;
  std::optional<std::string> hmin, hmax, gradation, max_anisotropy, norm;
  bool transfer = true;  // --no-transfer: no solution.vtu
};

// The case keys the command sets before the user's --set: the case's [spacing] table replaced by
// spacing.field = "hessian", spacing.file = SOL, spacing.array (a list for several arrays),
// spacing.complexity and the optional hmin, hmax, max_anisotropy, norm and metric_gradation (--gradation).
std::vector<CaseOverride> adapt_overrides(const AdaptOptions& options);

}  // namespace pdmesh
