// The case-file reader shared by app/config/case_file.cpp (keys, overrides, entry points) and
// app/config/case_sections.cpp (each section's values into CaseConfig): where a value came from, typed
// access that fails with "FILE:LINE:COL: ..." messages, and choices by name. Internal to those files.
#pragma once
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <string_view>
#include <utility>
#include <vector>
#include <fmt/format.h>
#include <toml++/toml.h>

#include "app/config/case_file.hpp"
#include "core/errors.hpp"
#include "core/input_file.hpp"

namespace pdmesh::case_detail {

namespace fs = std::filesystem;

inline const char* type_name(const toml::node& n) {
  switch (n.type()) {
    case toml::node_type::string:
      return "string";
    case toml::node_type::integer:
      return "integer";
    case toml::node_type::floating_point:
      return "float";
    case toml::node_type::boolean:
      return "boolean";
    case toml::node_type::array:
      return "array";
    case toml::node_type::table:
      return "table";
    case toml::node_type::date:
      return "date";
    case toml::node_type::time:
      return "time";
    case toml::node_type::date_time:
      return "date-time";
    default:
      return "nothing";
  }
}

// Everything a message needs to say where a value came from.
class Reader {
 public:
  Reader(std::string file, fs::path base_dir) : file_(std::move(file)), base_dir_(std::move(base_dir)) {}

  // Partial: the file alone, before the overrides. Every value it holds is checked; what only the
  // whole configuration decides (a required key, keys that must agree) is left to the full check.
  void set_partial(bool partial) { partial_ = partial; }
  bool partial() const { return partial_; }

  void mark_override(const std::string& key, const std::string& label) { labels_[key] = label; }

  // The override that set `key` (or one of its parents), if any.
  const std::string* override_label(const std::string& key) const {
    std::string k = key;
    for (;;) {
      if (auto it = labels_.find(k); it != labels_.end()) return &it->second;
      const auto cut = k.find_last_of(".[");
      if (cut == std::string::npos) return nullptr;
      k.resize(cut);
    }
  }

  std::string where(const std::string& key, const toml::source_region* at) const {
    if (const std::string* label = override_label(key)) return *label;
    if (at != nullptr && at->begin) return fmt::format("{}:{}:{}", file_, at->begin.line, at->begin.column);
    return file_;
  }

  [[noreturn]] void fail(const std::string& key, const toml::node* n, const std::string& what) const {
    throw InputError(fmt::format("{}: {}", where(key, n != nullptr ? &n->source() : nullptr), what));
  }

  [[noreturn]] void fail_at_key(const std::string& key, const toml::key& k, const std::string& what) const {
    throw InputError(fmt::format("{}: {}", where(key, &k.source()), what));
  }

  [[noreturn]] void wrong_type(const std::string& key, const toml::node& n, const char* expected) const {
    fail(key, &n, fmt::format("{} must be {}, got {}", key, expected, type_name(n)));
  }

  std::int64_t integer(const std::string& key, const toml::node& n) const {
    if (!n.is_integer()) wrong_type(key, n, "an integer");
    return n.as_integer()->get();
  }

  double number(const std::string& key, const toml::node& n) const {
    double v = 0;
    if (n.is_integer()) {
      v = static_cast<double>(n.as_integer()->get());
    } else if (n.is_floating_point()) {
      v = n.as_floating_point()->get();
    } else {
      wrong_type(key, n, "a number");
    }
    if (!std::isfinite(v)) fail(key, &n, fmt::format("{} must be finite, got {}", key, v));
    return v;
  }

  double positive(const std::string& key, const toml::node& n) const {
    const double v = number(key, n);
    if (!(v > 0)) fail(key, &n, fmt::format("{} must be > 0, got {}", key, v));
    return v;
  }

  std::string string(const std::string& key, const toml::node& n) const {
    if (!n.is_string()) wrong_type(key, n, "a string");
    return n.as_string()->get();
  }

  bool boolean(const std::string& key, const toml::node& n) const {
    if (!n.is_boolean()) wrong_type(key, n, "a boolean (true or false)");
    return n.as_boolean()->get();
  }

  const toml::array& array(const std::string& key, const toml::node& n) const {
    if (!n.is_array()) wrong_type(key, n, "an array");
    return *n.as_array();
  }

  std::vector<std::string> strings(const std::string& key, const toml::node& n) const {
    std::vector<std::string> out;
    const toml::array& a = array(key, n);
    for (std::size_t i = 0; i < a.size(); ++i) {
      const toml::node& e = *a.get(i);
      if (!e.is_string()) {
        fail(key, &e, fmt::format("{}[{}] must be a string, got {}", key, i, type_name(e)));
      }
      out.push_back(e.as_string()->get());
    }
    return out;
  }

  // Paths in the case file are relative to it; paths given by --set are relative to the
  // current directory, where the user typed them.
  fs::path resolve(const std::string& key, const std::string& p) const {
    const fs::path path(p);
    if (path.is_absolute() || override_label(key) != nullptr) return path;
    return base_dir_ / path;
  }

  const std::string& file() const { return file_; }

 private:
  std::string file_;
  fs::path base_dir_;
  std::map<std::string, std::string> labels_;
  bool partial_ = false;
};

inline const toml::node* find(const toml::table& root, std::string_view section, std::string_view key) {
  const toml::node* s = root.get(section);
  return s == nullptr ? nullptr : s->as_table()->get(key);
}

template <class T>
T choose(const Reader& r, const std::string& key, const toml::node& n,
         const std::vector<std::pair<std::string, T>>& choices) {
  const std::string v = r.string(key, n);
  std::string valid;
  for (const auto& [name, value] : choices) {
    if (name == v) return value;
    valid += (valid.empty() ? "" : ", ") + name;
  }
  r.fail(key, &n, fmt::format("{} must be one of {}, got '{}'", key, valid, quote_input(v)));
}

// The [[boundary_layer]] tables into c.boundary_layers (case_layers.cpp).
void read_boundary_layer_sections(const Reader& r, const toml::table& root, CaseConfig& c);
// The [[periodic]] tables into c.periodic (case_periodic.cpp): names, transform values; the curves
// and the transform are checked against the geometry once it is read (app/pipeline/periodic_pipeline).
void read_periodic_sections(const Reader& r, const toml::table& root, CaseConfig& c);
// The [motion] section into c.motion (case_motion.cpp): expressions parsed, steps and ranges checked;
// the curve names are checked against the geometry once it is read (app/pipeline/motion_pipeline.cpp).
void read_motion_section(const Reader& r, const toml::table& root, CaseConfig& c);
// The [spacing] keys of metric fields (case_metric_keys.cpp): read_metric_values reads and range-checks
// each value given; check_metric_keys (the whole configuration) checks that they agree with
// spacing.field and each other, and sets the defaults that depend on the source (array, sol).
void read_metric_values(const Reader& r, const toml::table& root, CaseConfig& c);
void check_metric_keys(const Reader& r, const toml::table& root, CaseConfig& c, const toml::node* file,
                       const toml::node* array);
const char* spacing_kind_name(SpacingKind kind);

// spacing.size, the [[refine]] tables into c.spacing.regions and [farfield] (case_sizes.cpp).
void read_size_sections(const Reader& r, const toml::table& root, CaseConfig& c);

// Every section's keys into `c` (case_sections.cpp), after the preset and the name.
void read_case_sections(const Reader& r, const toml::table& root, CaseConfig& c);

}  // namespace pdmesh::case_detail
