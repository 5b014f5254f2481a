// The case keys of pdmesh adapt (adapt_keys.hpp).
#include "app/config/adapt_keys.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <toml++/toml.h>

#include "app/config/option_overrides.hpp"

namespace pdmesh {

std::vector<CaseOverride> adapt_overrides(const AdaptOptions& o) {
  const std::string arrays = fmt::format("{}", fmt::join(o.arrays, ","));
  std::vector<CaseOverride> out;
  out.push_back({"spacing", "{}", "pdmesh adapt (the case's [spacing] is replaced)"});
  out.push_back({"spacing.field", "\"hessian\"", "pdmesh adapt"});
  out.push_back({"spacing.file", toml_string(o.solution), "--solution " + o.solution});
  if (o.arrays.size() == 1) {
    out.push_back({"spacing.array", toml_string(o.arrays.front()), "--array " + arrays});
  } else {
    toml::array list;
    for (const std::string& a : o.arrays) list.push_back(a);
    out.push_back({"spacing.array", toml_text(list), "--array " + arrays});
  }
  out.push_back({"spacing.complexity", o.complexity, "--complexity " + o.complexity});
  add_option_override(out, o.hmin, "--hmin", "spacing.hmin");
  add_option_override(out, o.hmax, "--hmax", "spacing.hmax");
  add_option_override(out, o.max_anisotropy, "--max-anisotropy", "spacing.max_anisotropy");
  add_option_override(out, o.norm, "--norm", "spacing.norm");
  add_option_override(out, o.gradation, "--gradation", "spacing.metric_gradation");
  return out;
}

}  // namespace pdmesh
