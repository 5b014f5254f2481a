// Case files: TOML parsing (toml++), --set overrides, unknown-key detection with suggestions,
// and validation of every key into CaseConfig. Messages are "FILE:LINE:COL: ...".
#include "app/case_file.hpp"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <cmath>
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <fstream>
#include <map>
#include <regex>
#include <sstream>
#include <toml++/toml.h>

#include "core/errors.hpp"

namespace pdmesh {

namespace fs = std::filesystem;

namespace {

// Tables that may hold further keys; every other key is a leaf.
const std::vector<std::string> kSections = {"geometry", "spacing", "boundary", "init", "simulation", "population", "cleanup", "output"};
const std::vector<std::string> kFormats = {"msh", "msh22", "vtu", "su2", "triangle", "png", "svg"};

const char* type_name(const toml::node& n) {
  switch (n.type()) {
    case toml::node_type::string: return "string";
    case toml::node_type::integer: return "integer";
    case toml::node_type::floating_point: return "float";
    case toml::node_type::boolean: return "boolean";
    case toml::node_type::array: return "array";
    case toml::node_type::table: return "table";
    case toml::node_type::date: return "date";
    case toml::node_type::time: return "time";
    case toml::node_type::date_time: return "date-time";
    default: return "nothing";
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

std::string nearest_key(const std::string& key) {
  std::string best;
  std::size_t best_distance = std::string::npos;
  for (const std::string& k : case_file_keys()) {
    const std::size_t d = edit_distance(key, k);
    if (d < best_distance) {
      best_distance = d;
      best = k;
    }
  }
  // A suggestion that needs to change most of the key is noise.
  return best_distance <= std::max<std::size_t>(2, key.size() / 3) ? best : std::string();
}

[[noreturn]] void unknown_key(const Reader& r, const std::string& key, const toml::key& k) {
  const std::string suggestion = nearest_key(key);
  if (!suggestion.empty()) {
    r.fail_at_key(key, k, fmt::format("unknown key '{}'; did you mean '{}'?", key, suggestion));
  }
  r.fail_at_key(key, k, fmt::format("unknown key '{}'; valid keys are listed in docs/cli.md", key));
}

bool is_known(const std::string& key) {
  const auto& keys = case_file_keys();
  return std::find(keys.begin(), keys.end(), key) != keys.end();
}

bool is_section(const std::string& key) {
  return std::find(kSections.begin(), kSections.end(), key) != kSections.end();
}

// Rejects keys that are not in the schema. An unknown table is reported by its first leaf, so that
// "[simulaton] iterations = 5" says "unknown key 'simulaton.iterations'".
void check_keys(const Reader& r, const toml::table& t, const std::string& prefix) {
  for (const auto& [k, node] : t) {
    std::string key = prefix.empty() ? std::string(k.str()) : prefix + "." + std::string(k.str());
    if (is_section(key)) {
      if (!node.is_table()) r.wrong_type(key, node, "a table");
      check_keys(r, *node.as_table(), key);
      continue;
    }
    if (key == "simulation.dt_initial" && node.is_table()) {
      check_keys(r, *node.as_table(), key);
      continue;
    }
    if (is_known(key)) continue;
    const toml::node* leaf = &node;
    const toml::key* leaf_key = &k;
    while (leaf->is_table() && !leaf->as_table()->empty()) {
      const auto first = leaf->as_table()->begin();
      key += '.';
      key += first->first.str();
      leaf_key = &first->first;
      leaf = &first->second;
    }
    unknown_key(r, key, *leaf_key);
  }
}

// Keys whose value is a string: an override such as "spacing.expression=2" means the text.
bool is_string_key(const std::string& key) {
  return key == "name" || key == "preset" || key == "geometry.curves" || key == "boundary.nodes" ||
         key == "spacing.field" || key == "spacing.expression" || key == "spacing.file" || key == "spacing.array" ||
         key == "init.method" ||
         key == "simulation.device" || key == "simulation.precision" || key == "simulation.r0_rule" ||
         key == "simulation.stop" ||
         key == "output.color_by";
}

// Parses an override's value as TOML; a bare word that is not TOML (random, a.crv) is a string.
toml::table override_value(const CaseOverride& o) {
  try {
    toml::table t = toml::parse("v = " + o.value, o.label);
    if (t.size() == 1 && t.contains("v") && (t.get("v")->is_string() || !is_string_key(o.key))) return t;
  } catch (const toml::parse_error&) {
  }
  toml::table t;
  t.insert_or_assign("v", o.value);
  return t;
}

void apply_override(toml::table& root, const CaseOverride& o, Reader& r) {
  std::vector<std::string> parts;
  std::stringstream ss(o.key);
  for (std::string part; std::getline(ss, part, '.');) parts.push_back(part);
  if (parts.empty() || std::any_of(parts.begin(), parts.end(), [](auto& s) { return s.empty(); })) {
    throw InputError(fmt::format("{}: '{}' is not a key (expected section.key)", o.label, o.key));
  }
  toml::table* t = &root;
  std::string path;
  for (std::size_t i = 0; i + 1 < parts.size(); ++i) {
    if (i > 0) path += '.';
    path += parts[i];
    toml::node* n = t->get(parts[i]);
    if (n == nullptr) {
      t->insert_or_assign(parts[i], toml::table{});
      n = t->get(parts[i]);
    } else if (!n->is_table()) {
      throw InputError(fmt::format("{}: cannot set '{}': '{}' is not a table (it is {} {})", o.label, o.key, path,
                                   std::string_view("aeiou").find(type_name(*n)[0]) == std::string_view::npos ? "a" : "an",
                                   type_name(*n)));
    }
    t = n->as_table();
  }
  const toml::table value = override_value(o);
  const toml::node& v = *value.get("v");
  if (o.append) {
    toml::node* existing = t->get(parts.back());
    if (existing == nullptr) {
      t->insert_or_assign(parts.back(), toml::array{});
      existing = t->get(parts.back());
    }
    if (!existing->is_array()) r.wrong_type(o.key, *existing, "an array");
    existing->as_array()->push_back(v);
    r.mark_override(fmt::format("{}[{}]", o.key, existing->as_array()->size() - 1), o.label);
  } else {
    t->insert_or_assign(parts.back(), v);
    r.mark_override(o.key, o.label);
  }
}

const toml::node* find(const toml::table& root, std::string_view section, std::string_view key) {
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
  r.fail(key, &n, fmt::format("{} must be one of {}, got '{}'", key, valid, v));
}

bool is_plain_name(const std::string& s) {
  static const std::regex plain("[A-Za-z0-9_.+-]+");
  return std::regex_match(s, plain);
}

void read_geometry_section(const Reader& r, const toml::table& root, CaseConfig& c) {
  const toml::node* files = find(root, "geometry", "files");
  if (!c.geometry.given_curves.empty()) {
    // Curves given in memory (case_for_curves) are the geometry; files would be a second one.
    if (files != nullptr) r.fail("geometry.files", files, "geometry.files cannot be set: the geometry is given as curves");
  } else if (files == nullptr && !r.partial()) {
    throw InputError(fmt::format("{}: geometry.files is required (the .crv/.dat/.poly files to mesh)", r.file()));
  }
  if (files != nullptr && c.geometry.given_curves.empty()) {
    const std::vector<std::string> names = r.strings("geometry.files", *files);
    if (names.empty()) r.fail("geometry.files", files, "geometry.files must name at least one file");
    for (const std::string& f : names) c.geometry.files.push_back(r.resolve("geometry.files", f));
  }
  if (const toml::node* n = find(root, "geometry", "curve_names")) {
    c.geometry.curve_names = r.strings("geometry.curve_names", *n);
    for (const std::string& name : c.geometry.curve_names) {
      // Names appear in node files and mesh files, which separate fields by white space.
      if (!is_plain_name(name)) {
        r.fail("geometry.curve_names", n,
               fmt::format("geometry.curve_names: '{}' is not a plain name (letters, digits, _ . + -)", name));
      }
    }
  }
  if (const toml::node* n = find(root, "geometry", "join_tolerance")) {
    c.geometry.join_tolerance = r.positive("geometry.join_tolerance", *n);
  }
  if (const toml::node* n = find(root, "geometry", "corner_angle")) {
    const double a = r.number("geometry.corner_angle", *n);
    if (!(a > 0 && a < 180)) {
      r.fail("geometry.corner_angle", n, fmt::format("geometry.corner_angle must be in (0, 180) degrees, got {}", a));
    }
    c.geometry.corner_angle = a;
  }
  if (const toml::node* n = find(root, "geometry", "curves")) {
    c.geometry.curves =
        choose<CurveKind>(r, "geometry.curves", *n, {{"polyline", CurveKind::Polyline}, {"smooth", CurveKind::Smooth}});
  }
}

void read_boundary_section(const Reader& r, const toml::table& root, CaseConfig& c) {
  if (const toml::node* n = find(root, "boundary", "nodes")) {
    c.boundary.nodes = choose<BoundaryNodeRule>(r, "boundary.nodes", *n,
                                                {{"input", BoundaryNodeRule::Input}, {"spacing", BoundaryNodeRule::Spacing}});
  }
}

void read_spacing_section(const Reader& r, const toml::table& root, CaseConfig& c) {
  const toml::node* expression = find(root, "spacing", "expression");
  const toml::node* file = find(root, "spacing", "file");
  const toml::node* array = find(root, "spacing", "array");
  const toml::node* field = find(root, "spacing", "field");
  if (expression != nullptr) c.spacing.expression = r.string("spacing.expression", *expression);
  if (file != nullptr) {
    const std::string f = r.string("spacing.file", *file);
    std::string ext = fs::path(f).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char ch) { return static_cast<char>(std::tolower(ch)); });
    if (ext != ".vtu" && ext != ".msh") {
      r.fail("spacing.file", file, fmt::format("spacing.file '{}' must be a .vtu or .msh triangle mesh", f));
    }
    c.spacing.file = r.resolve("spacing.file", f);
  }
  if (array != nullptr) {
    c.spacing.array = r.string("spacing.array", *array);
    if (c.spacing.array.empty()) r.fail("spacing.array", array, "spacing.array must not be empty");
  }
  // An expression or a file alone selects its field; naming kinds contradictorily is an error.
  if (field != nullptr) {
    c.spacing.field = choose<SpacingKind>(
        r, "spacing.field", *field,
        {{"boundary", SpacingKind::Boundary}, {"expression", SpacingKind::Expression}, {"mesh", SpacingKind::Mesh}});
  }
  if (r.partial()) return;  // the rest is how the keys agree: the whole configuration decides
  if (field == nullptr) {
    if (expression != nullptr && file != nullptr)
      r.fail("spacing.file", file, "spacing.expression and spacing.file are both set; choose one with spacing.field");
    c.spacing.field = expression != nullptr ? SpacingKind::Expression : file != nullptr ? SpacingKind::Mesh : SpacingKind::Boundary;
  }
  const char* name = c.spacing.field == SpacingKind::Boundary ? "boundary" : c.spacing.field == SpacingKind::Expression ? "expression" : "mesh";
  if (c.spacing.field == SpacingKind::Expression && c.spacing.expression.empty()) {
    r.fail("spacing.field", field, "spacing.field is 'expression' but spacing.expression is missing or empty");
  }
  if (c.spacing.field == SpacingKind::Mesh && file == nullptr) {
    r.fail("spacing.field", field, "spacing.field is 'mesh' but spacing.file (a .vtu or .msh background mesh) is missing");
  }
  if (c.spacing.field != SpacingKind::Expression && expression != nullptr) {
    r.fail("spacing.expression", expression, fmt::format("spacing.expression is set but spacing.field is '{}'", name));
  }
  if (c.spacing.field != SpacingKind::Mesh && file != nullptr) {
    r.fail("spacing.file", file, fmt::format("spacing.file is set but spacing.field is '{}'", name));
  }
  if (c.spacing.field != SpacingKind::Mesh && array != nullptr) {
    r.fail("spacing.array", array, fmt::format("spacing.array is set but spacing.field is '{}'", name));
  }
  if (const toml::node* n = find(root, "spacing", "scale")) c.spacing.scale = r.positive("spacing.scale", *n);
  if (const toml::node* n = find(root, "spacing", "gradation")) {
    c.spacing.gradation = r.number("spacing.gradation", *n);
    if (!(c.spacing.gradation >= 0.0 && c.spacing.gradation <= 10.0))
      r.fail("spacing.gradation", n, fmt::format("spacing.gradation must be in [0, 10] (0 = off), got {}", c.spacing.gradation));
  }
  if (const toml::node* n = find(root, "spacing", "rows_in_gap")) {
    c.spacing.rows_in_gap = r.number("spacing.rows_in_gap", *n);
    if (!(c.spacing.rows_in_gap == 0.0 || (c.spacing.rows_in_gap >= 1.0 && c.spacing.rows_in_gap <= 100.0)))
      r.fail("spacing.rows_in_gap", n,
             fmt::format("spacing.rows_in_gap must be 0 (off) or in [1, 100], got {}", c.spacing.rows_in_gap));
  }
  if (const toml::node* n = find(root, "spacing", "curvature_angle")) {
    c.spacing.curvature_angle = r.number("spacing.curvature_angle", *n);
    if (!(c.spacing.curvature_angle >= 0.0 && c.spacing.curvature_angle <= 90.0))
      r.fail("spacing.curvature_angle", n,
             fmt::format("spacing.curvature_angle must be in [0, 90] degrees (0 = off), got {}", c.spacing.curvature_angle));
  }
}

std::uint64_t non_negative(const Reader& r, const std::string& key, const toml::node& n) {
  const std::int64_t v = r.integer(key, n);
  if (v < 0) r.fail(key, &n, fmt::format("{} must be >= 0, got {}", key, v));
  return static_cast<std::uint64_t>(v);
}

void read_init_section(const Reader& r, const toml::table& root, CaseConfig& c) {
  if (const toml::node* n = find(root, "init", "method")) {
    c.init.method = choose<InitMethod>(r, "init.method", *n,
                                       {{"structured", InitMethod::Structured}, {"random", InitMethod::Random},
                                        {"hexagonal", InitMethod::Hexagonal}});
  }
  if (const toml::node* n = find(root, "init", "seed")) c.init.seed = non_negative(r, "init.seed", *n);
  if (const toml::node* n = find(root, "init", "total")) c.init.total = non_negative(r, "init.total", *n);
}

bool valid_device(const std::string& d) {
  static const std::regex device("auto|host|opencl|opencl:[0-9]+:[0-9]+");
  return std::regex_match(d, device);
}

void read_simulation_section(const Reader& r, const toml::table& root, CaseConfig& c) {
  auto& s = c.simulation;
  if (const toml::node* n = find(root, "simulation", "iterations")) {
    const std::int64_t v = r.integer("simulation.iterations", *n);
    if (v < 0) r.fail("simulation.iterations", n, fmt::format("simulation.iterations must be >= 0, got {}", v));
    s.iterations = v;
  }
  if (const toml::node* n = find(root, "simulation", "stop")) {
    s.stop = choose<StopRule>(r, "simulation.stop", *n, {{"converged", StopRule::Converged}, {"iterations", StopRule::Iterations}});
  }
  for (auto [key, out, hi] : {std::tuple{"stop_aspect", &s.stop_aspect, 0.1}, {"stop_angle", &s.stop_angle, 10.0}})
    if (const toml::node* n = find(root, "simulation", key)) {
      const std::string name = std::string("simulation.") + key;
      *out = r.number(name, *n);
      if (!(*out >= 0.0 && *out <= hi)) r.fail(name, n, fmt::format("{} must be in [0, {}], got {}", name, hi, *out));
    }
  if (const toml::node* n = find(root, "simulation", "dt_initial")) {
    if (n->is_table()) {
      const toml::table& per = *n->as_table();
      if (const toml::node* d = per.get("structured")) s.dt_structured = r.positive("simulation.dt_initial.structured", *d);
      if (const toml::node* d = per.get("random")) s.dt_random = r.positive("simulation.dt_initial.random", *d);
    } else if (n->is_integer() || n->is_floating_point()) {
      s.dt_structured = s.dt_random = r.positive("simulation.dt_initial", *n);
    } else {
      r.wrong_type("simulation.dt_initial", *n, "a number or a table { structured = ..., random = ... }");
    }
  }
  if (const toml::node* n = find(root, "simulation", "cutoff")) s.cutoff = r.positive("simulation.cutoff", *n);
  if (const toml::node* n = find(root, "simulation", "lj_a")) s.lj_a = r.positive("simulation.lj_a", *n);
  if (const toml::node* n = find(root, "simulation", "device")) {
    s.device = r.string("simulation.device", *n);
    if (!valid_device(s.device)) {
      r.fail("simulation.device", n,
             fmt::format("simulation.device must be auto, host, opencl or opencl:P:D, got '{}'", s.device));
    }
  }
  if (const toml::node* n = find(root, "simulation", "precision")) {
    s.precision = choose<Precision>(r, "simulation.precision", *n, {{"double", Precision::Double}, {"float", Precision::Float}, {"auto", Precision::Auto}});
  }
  if (const toml::node* n = find(root, "simulation", "stability_factor")) {
    s.stability_factor = r.number("simulation.stability_factor", *n);
    if (!(s.stability_factor >= 0.0 && s.stability_factor <= 1.0)) {
      r.fail("simulation.stability_factor", n,
             fmt::format("simulation.stability_factor must be in [0, 1] (0 = the thesis' time step), got {}",
                         s.stability_factor));
    }
  }
  if (const toml::node* n = find(root, "simulation", "r0_rule")) {
    s.r0_any_direction = choose<bool>(r, "simulation.r0_rule", *n, {{"force_direction", false}, {"any_direction", true}});
  }
}

// A threshold given as one number (constant over the run) or [first, last] (ramped from the first
// event to the last), each in (lo, hi).
PopulationRamp read_ramp(const Reader& r, const std::string& key, const toml::node& n, double lo, double hi) {
  PopulationRamp ramp;
  if (n.is_array()) {
    const toml::array& a = *n.as_array();
    if (a.size() != 2) r.fail(key, &n, fmt::format("{} must be a number or [first, last], got {} numbers", key, a.size()));
    ramp = {r.number(key + "[0]", *a.get(0)), r.number(key + "[1]", *a.get(1))};
  } else {
    ramp.first = ramp.last = r.number(key, n);
  }
  for (double v : {ramp.first, ramp.last})
    if (!(v > lo && v < hi)) r.fail(key, &n, fmt::format("{} must be in ({}, {}), got {}", key, lo, hi, v));
  return ramp;
}

void read_population_section(const Reader& r, const toml::table& root, CaseConfig& c) {
  PopulationOptions& p = c.population;
  const auto integer_in = [&](const char* key, std::int64_t lo, std::int64_t hi, int& out) {
    if (const toml::node* n = find(root, "population", key)) {
      const std::string name = std::string("population.") + key;
      const std::int64_t v = r.integer(name, *n);
      if (v < lo || v > hi) r.fail(name, n, fmt::format("{} must be in {}..{}, got {}", name, lo, hi, v));
      out = static_cast<int>(v);
    }
  };
  if (const toml::node* n = find(root, "population", "enabled")) p.enabled = r.boolean("population.enabled", *n);
  integer_in("every", 1, 1'000'000'000, p.every);
  integer_in("start", 0, 2'000'000'000, p.start);
  integer_in("remove_valence", 0, 5, p.remove_valence);
  integer_in("settle_events", 1, kPopulationMaxSettleEvents, p.settle_events);
  if (const toml::node* n = find(root, "population", "settle")) {
    p.settle = r.number("population.settle", *n);
    if (!(p.settle >= 0.0 && p.settle <= 0.1))
      r.fail("population.settle", n,
             fmt::format("population.settle must be in [0, 0.1] (a fraction of the nodes), got {}", p.settle));
  }
  if (const toml::node* n = find(root, "population", "stop")) {
    p.stop = r.number("population.stop", *n);
    if (!(p.stop > 0.0 && p.stop <= 1.0))
      r.fail("population.stop", n, fmt::format("population.stop must be in (0, 1] (a fraction of the run), got {}", p.stop));
  }
  // An equilateral lattice has circumradius q / sqrt(3) = 0.577 q: insert must stay above it.
  if (const toml::node* n = find(root, "population", "insert")) p.insert = read_ramp(r, "population.insert", *n, 0.6, 3.0);
  if (const toml::node* n = find(root, "population", "merge")) p.merge = read_ramp(r, "population.merge", *n, 0.0, 1.0);
  const toml::node* merge = find(root, "population", "merge");
  if (std::max(p.merge.first, p.merge.last) >= std::min(p.insert.first, p.insert.last))
    r.fail("population.merge", merge ? merge : find(root, "population", "insert"),
           "population.merge must stay below population.insert (a new node would be merged again)");
  if (const toml::node* n = find(root, "population", "boundary")) p.boundary = r.boolean("population.boundary", *n);
  const toml::node* split = find(root, "population", "boundary_split");
  if (split) p.boundary_split = r.number("population.boundary_split", *split);
  // A split gap's halves must not be short enough to merge again (churn).
  const double merge_max = std::max(p.merge.first, p.merge.last);
  if (!(p.boundary_split > 2.0 * merge_max && p.boundary_split < 10.0))
    r.fail("population.boundary_split", split ? split : merge,
           fmt::format("population.boundary_split must be in (2 x population.merge = {}, 10), got {}", 2.0 * merge_max,
                       p.boundary_split));
}

void read_cleanup_section(const Reader& r, const toml::table& root, CaseConfig& c) {
  auto& k = c.cleanup;
  if (const toml::node* n = find(root, "cleanup", "enabled")) k.enabled = r.boolean("cleanup.enabled", *n);
  if (const toml::node* n = find(root, "cleanup", "min_angle")) {
    k.min_angle = r.number("cleanup.min_angle", *n);
    if (!(k.min_angle > 0.0 && k.min_angle < 60.0))
      r.fail("cleanup.min_angle", n, fmt::format("cleanup.min_angle must be in (0, 60) degrees, got {}", k.min_angle));
  }
  if (const toml::node* n = find(root, "cleanup", "iterations")) {
    k.iterations = r.integer("cleanup.iterations", *n);
    if (k.iterations < 1 || k.iterations > 1000)
      r.fail("cleanup.iterations", n, fmt::format("cleanup.iterations must be in 1..1000, got {}", k.iterations));
  }
  if (const toml::node* n = find(root, "cleanup", "topology")) k.topology = r.boolean("cleanup.topology", *n);
  if (const toml::node* n = find(root, "cleanup", "split_boundary"))
    k.split_boundary = r.boolean("cleanup.split_boundary", *n);
}

ViewWindow read_view(const Reader& r, const toml::node& entry, std::size_t i) {
  const std::string key = fmt::format("output.views[{}]", i);
  if (!entry.is_table()) r.wrong_type(key, entry, "a table { name = ..., window = [x0, y0, x1, y1] }");
  ViewWindow v;
  v.name = fmt::format("view{}", i + 1);
  const toml::node* window = nullptr;
  for (const auto& [k, n] : *entry.as_table()) {
    const std::string sub = key + "." + std::string(k.str());
    if (k == "name") {
      v.name = r.string(sub, n);
      if (!is_plain_name(v.name)) {
        r.fail(sub, &n, fmt::format("{} '{}' must be a plain name (letters, digits, _ . + -)", sub, v.name));
      }
    } else if (k == "window") {
      window = &n;
    } else {
      const std::string hint = edit_distance(k.str(), "name") <= 2 ? "name" : "window";
      r.fail_at_key(sub, k, fmt::format("unknown key '{}'; did you mean '{}.{}'?", sub, key, hint));
    }
  }
  if (window == nullptr) r.fail(key, &entry, fmt::format("{} needs window = [x0, y0, x1, y1]", key));
  const toml::array& a = r.array(key + ".window", *window);
  if (a.size() != 4) r.fail(key + ".window", window, fmt::format("{}.window must have 4 numbers, got {}", key, a.size()));
  double w[4];
  for (std::size_t j = 0; j < 4; ++j) w[j] = r.number(fmt::format("{}.window[{}]", key, j), *a.get(j));
  if (!(w[0] < w[2] && w[1] < w[3])) {
    r.fail(key + ".window", window,
           fmt::format("{}.window [{}, {}, {}, {}] needs x0 < x1 and y0 < y1", key, w[0], w[1], w[2], w[3]));
  }
  v.window.lo = {w[0], w[1]};
  v.window.hi = {w[2], w[3]};
  return v;
}

void read_output_section(const Reader& r, const toml::table& root, CaseConfig& c) {
  if (const toml::node* n = find(root, "output", "formats")) {
    c.output.formats = r.strings("output.formats", *n);
    for (const std::string& f : c.output.formats) {
      if (std::find(kFormats.begin(), kFormats.end(), f) == kFormats.end()) {
        r.fail("output.formats", n,
               fmt::format("output.formats: unknown format '{}'; valid formats are {}", f, fmt::join(kFormats, ", ")));
      }
    }
    if (c.output.wants("msh") && c.output.wants("msh22"))
      r.fail("output.formats", n, "output.formats: 'msh' and 'msh22' both write mesh.msh; ask for one of them");
  }
  if (const toml::node* n = find(root, "output", "color_by")) {
    c.output.color_by = choose<std::string>(r, "output.color_by", *n,
                                            {{"none", "none"}, {"min_angle", "min_angle"}, {"max_angle", "max_angle"},
                                             {"aspect_ratio", "aspect_ratio"}, {"skewness", "skewness"},
                                             {"condition_number", "condition_number"}, {"min_jacobian", "min_jacobian"}});
  }
  if (const toml::node* n = find(root, "output", "tree_overlay")) c.output.tree_overlay = r.boolean("output.tree_overlay", *n);
  if (const toml::node* n = find(root, "output", "spacing_picture"))
    c.output.spacing_picture = r.boolean("output.spacing_picture", *n);
  if (const toml::node* n = find(root, "output", "views")) {
    const toml::array& a = r.array("output.views", *n);
    for (std::size_t i = 0; i < a.size(); ++i) {
      ViewWindow v = read_view(r, *a.get(i), i);
      for (const ViewWindow& earlier : c.output.views) {
        if (earlier.name == v.name) {
          r.fail(fmt::format("output.views[{}]", i), a.get(i), fmt::format("view name '{}' is used twice", v.name));
        }
      }
      c.output.views.push_back(std::move(v));
    }
  }
}

CaseConfig check_values(const toml::table& root, const Reader& r, CaseConfig c) {
  check_keys(r, root, "");
  // The preset first: it sets the defaults that every other key then overrides.
  if (const toml::node* n = root.get("preset")) {
    apply_preset(c, choose<Preset>(r, "preset", *n, {{"best", Preset::Best}, {"thesis", Preset::Thesis}}));
  }
  if (const toml::node* n = root.get("name")) {
    c.name = r.string("name", *n);
    if (c.name.empty()) r.fail("name", n, "name must not be empty");
  }
  read_geometry_section(r, root, c);
  read_spacing_section(r, root, c);
  read_boundary_section(r, root, c);
  read_init_section(r, root, c);
  read_simulation_section(r, root, c);
  read_population_section(r, root, c);
  read_cleanup_section(r, root, c);
  read_output_section(r, root, c);
  return c;
}

CaseConfig validate(toml::table& root, Reader& r, const std::vector<CaseOverride>& overrides, const CaseConfig& c) {
  if (!overrides.empty()) {
    // The file is checked whole first: a wrong value in it (iterations = "many") is an error even when
    // an option replaces it, since the file is wrong for every other run.
    Reader file_only = r;
    file_only.set_partial(true);
    (void)check_values(root, file_only, c);
  }
  for (const CaseOverride& o : overrides) apply_override(root, o, r);
  return check_values(root, r, c);
}

}  // namespace

bool CaseConfig::Output::wants(const std::string& format) const {
  return std::find(formats.begin(), formats.end(), format) != formats.end();
}

const std::vector<std::string>& case_file_keys() {
  static const std::vector<std::string> keys = {
      "name", "preset",
      "geometry.files", "geometry.curve_names", "geometry.join_tolerance", "geometry.corner_angle",
      "geometry.curves", "spacing.field", "spacing.expression", "spacing.file", "spacing.array", "spacing.scale",
      "spacing.gradation", "spacing.rows_in_gap", "spacing.curvature_angle", "boundary.nodes",
      "init.method", "init.seed", "init.total",
      "simulation.iterations", "simulation.stop", "simulation.stop_aspect", "simulation.stop_angle",
      "simulation.dt_initial", "simulation.dt_initial.structured",
      "simulation.dt_initial.random", "simulation.cutoff", "simulation.lj_a", "simulation.device",
      "simulation.precision", "simulation.r0_rule", "simulation.stability_factor",
      "population.enabled", "population.every", "population.start", "population.stop", "population.insert",
      "population.merge", "population.remove_valence", "population.boundary", "population.boundary_split",
      "population.settle", "population.settle_events",
      "cleanup.enabled", "cleanup.min_angle", "cleanup.iterations", "cleanup.topology", "cleanup.split_boundary",
      "output.formats", "output.tree_overlay", "output.views", "output.color_by", "output.spacing_picture",
  };
  return keys;
}

std::size_t edit_distance(std::string_view a, std::string_view b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diagonal = up;
    }
  }
  return row[b.size()];
}

CaseOverride parse_set_option(const std::string& text) {
  const auto eq = text.find('=');
  if (eq == std::string::npos || eq == 0) {
    throw InputError(fmt::format("--set {}: expected section.key=VALUE", text));
  }
  return {text.substr(0, eq), text.substr(eq + 1), "--set " + text};
}

CaseConfig parse_case_text(std::string_view text, const fs::path& source, const std::vector<CaseOverride>& overrides) {
  toml::table root;
  try {
    root = toml::parse(text, source.string());
  } catch (const toml::parse_error& e) {
    throw InputError(fmt::format("{}:{}:{}: {}", source.string(), e.source().begin.line, e.source().begin.column,
                                 e.description()));
  }
  Reader r(source.string(), source.parent_path());
  CaseConfig c;
  c.source = source;
  // The case directory names the case unless the file says otherwise.
  const fs::path dir = fs::absolute(source).parent_path();
  c.name = dir.filename().empty() ? source.stem().string() : dir.filename().string();
  return validate(root, r, overrides, std::move(c));
}

CaseConfig load_case_file(const fs::path& case_file, const std::vector<CaseOverride>& overrides) {
  std::ifstream in(case_file, std::ios::binary);
  if (!in) {
    throw InputError(fmt::format("cannot read case file '{}': {}", case_file.string(), std::strerror(errno)));
  }
  std::ostringstream text;
  text << in.rdbuf();
  return parse_case_text(text.str(), case_file, overrides);
}

CaseConfig case_for_geometry_file(const fs::path& geometry_file, const std::vector<CaseOverride>& overrides) {
  return case_for_geometry_files({geometry_file}, overrides);
}

CaseConfig case_for_geometry_files(const std::vector<fs::path>& geometry_files,
                                   const std::vector<CaseOverride>& overrides) {
  if (geometry_files.empty()) throw InputError("no geometry file given");
  toml::array files;
  for (const fs::path& f : geometry_files) files.push_back(fs::absolute(f).string());
  toml::table root;
  root.insert_or_assign("geometry", toml::table{{"files", std::move(files)}});
  Reader r(geometry_files.front().string(), fs::current_path());
  CaseConfig c;
  c.source = geometry_files.front();
  c.name = geometry_files.front().stem().string();
  return validate(root, r, overrides, std::move(c));
}

CaseConfig case_for_curves(std::vector<RawCurve> curves, const std::string& source,
                           const std::vector<CaseOverride>& overrides) {
  if (curves.empty()) throw InputError(fmt::format("{}: the geometry has no curves", source));
  toml::table root;
  Reader r(source, fs::current_path());
  CaseConfig c;
  c.source = source;
  c.name = source;
  c.geometry.given_curves = std::move(curves);
  return validate(root, r, overrides, std::move(c));
}

}  // namespace pdmesh
