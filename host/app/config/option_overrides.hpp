// Command-line options as case-file overrides (app/config/case_file.hpp, CaseOverride), shared by the
// commands that translate their options into case keys (app/cli/cli.cpp, app/config/adapt_keys.cpp).
#pragma once
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <toml++/toml.h>

#include "app/config/case_file.hpp"

namespace pdmesh {

// A TOML value as CaseOverride::value holds it (toml++'s formatting: strings quoted and escaped).
inline std::string toml_text(const toml::node& n) {
  std::ostringstream s;
  n.visit([&](const auto& v) { s << v; });
  return s.str();
}

// A string as a TOML string value.
inline std::string toml_string(const std::string& text) { return toml_text(toml::value<std::string>(text)); }

// `--option VALUE` (when given) as the override of `key`, labelled "--option VALUE" in messages.
inline void add_option_override(std::vector<CaseOverride>& out, const std::optional<std::string>& value,
                                const char* option, const char* key) {
  if (value) out.push_back({key, *value, fmt::format("{} {}", option, *value)});
}

}  // namespace pdmesh
