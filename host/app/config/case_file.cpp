// Case files: TOML parsing (toml++), --set overrides, unknown-key detection with suggestions, and the
// entry points; each section's values are read in app/config/case_sections.cpp, through app/config/case_reader.hpp.
// Messages are "FILE:LINE:COL: ...".
#include "app/config/case_file.hpp"

#include <algorithm>
#include <fmt/format.h>
#include <toml++/toml.h>

#include "app/config/case_reader.hpp"
#include "core/errors.hpp"
#include "core/input_file.hpp"
#include "io/mesh_formats.hpp"

namespace pdmesh {

namespace fs = std::filesystem;

using case_detail::choose;
using case_detail::read_case_sections;
using case_detail::Reader;
using case_detail::type_name;

namespace {

// Tables that may hold further keys; every other key is a leaf.
constexpr std::size_t kMaxNameBytes = 200;

const std::vector<std::string> kSections = {"geometry",   "spacing", "boundary", "init",     "simulation",
                                            "population", "cleanup", "output",   "farfield", "motion"};

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
  // No key is longer than 40 characters: a longer one gets no suggestion (and edit_distance's cost
  // grows with the product of the lengths).
  const std::string suggestion = key.size() <= 64 ? nearest_key(key) : std::string();
  if (!suggestion.empty()) {
    r.fail_at_key(key, k, fmt::format("unknown key '{}'; did you mean '{}'?", quote_input(key), suggestion));
  }
  r.fail_at_key(key, k, fmt::format("unknown key '{}'; valid keys are listed in docs/cli.md", quote_input(key)));
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
    if (key == "boundary_layer" || key == "refine" || key == "periodic") {
      // [boundary_layer] once or [[boundary_layer]] per curve set (the same for [[refine]]): each
      // table's keys are checked.
      if (node.is_table()) {
        check_keys(r, *node.as_table(), key);
      } else if (node.is_array()) {
        for (const toml::node& e : *node.as_array()) {
          if (!e.is_table()) r.wrong_type(key, e, fmt::format("a table ([[{}]])", key).c_str());
          check_keys(r, *e.as_table(), key);
        }
      } else {
        r.wrong_type(key, node, fmt::format("a table ([[{}]])", key).c_str());
      }
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
  return key == "name" || key == "preset" || key == "geometry.curves" || key == "geometry.projection" ||
         key == "boundary.nodes" || key == "spacing.field" || key == "spacing.expression" || key == "spacing.file" ||
         key == "spacing.array" || key == "spacing.h1" || key == "spacing.h2" || key == "spacing.angle" ||
         key == "spacing.m11" || key == "spacing.m12" || key == "spacing.m22" || key == "spacing.sol" ||
         key == "spacing.function" || key == "init.method" || key == "simulation.device" ||
         key == "simulation.precision" || key == "simulation.r0_rule" || key == "simulation.stop" ||
         key == "output.color_by" || key == "farfield.shape" || key == "farfield.cavities" || key == "motion.rotate";
}

// Parses an override's value as TOML; a bare word that is not TOML (random, a.crv) is a string.
toml::table override_value(const CaseOverride& o) {
  try {
    toml::table t = toml::parse("v = " + o.value, o.label);
    // spacing.array may also be a list of names (several arrays of a Hessian metric).
    const toml::node* v = t.get("v");
    if (t.size() == 1 && v != nullptr &&
        (v->is_string() || !is_string_key(o.key) || (o.key == "spacing.array" && v->is_array())))
      return t;
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
    if (o.if_unset && n != nullptr && !n->is_table()) return;  // set above the key: the file's value stands
    if (n == nullptr) {
      t->insert_or_assign(parts[i], toml::table{});
      n = t->get(parts[i]);
    } else if (!n->is_table()) {
      throw InputError(fmt::format(
          "{}: cannot set '{}': '{}' is not a table (it is {} {})", o.label, o.key, path,
          std::string_view("aeiou").find(type_name(*n)[0]) == std::string_view::npos ? "a" : "an", type_name(*n)));
    }
    t = n->as_table();
  }
  if (o.if_unset && t->get(parts.back()) != nullptr) return;
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

CaseConfig check_values(const toml::table& root, const Reader& r, CaseConfig c) {
  check_keys(r, root, "");
  // The preset first (best unless the file names one): it sets the defaults that every other key then
  // overrides. c holds the long preset's values (CaseConfig's initializers) until then.
  Preset preset = Preset::Best;
  if (const toml::node* n = root.get("preset")) {
    preset = choose<Preset>(
        r, "preset", *n,
        {{"best", Preset::Best}, {"thesis", Preset::Thesis}, {"long", Preset::Long}, {"fast", Preset::Fast}});
  }
  apply_preset(c, preset);
  if (const toml::node* n = root.get("name")) {
    c.name = r.string("name", *n);
    if (c.name.empty()) r.fail("name", n, "name must not be empty");
    // The name titles pictures: a line of text, not a payload.
    if (c.name.size() > kMaxNameBytes) {
      r.fail(
          "name", n,
          fmt::format("name has {} bytes, more than {} (got '{}')", c.name.size(), kMaxNameBytes, quote_input(c.name)));
    }
    const auto control = [](char ch) { return static_cast<unsigned char>(ch) < 0x20 || ch == 0x7f; };
    if (std::any_of(c.name.begin(), c.name.end(), control)) {
      r.fail("name", n, fmt::format("name holds a control character (got '{}')", quote_input(c.name)));
    }
  }
  read_case_sections(r, root, c);
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

// The valid keys of each case-file section (top-level keys first); case_file_keys() joins them.
const std::vector<std::string>& top_level_keys() {
  static const std::vector<std::string> keys = {
      "name",
      "preset",
  };
  return keys;
}

const std::vector<std::string>& geometry_keys() {
  static const std::vector<std::string> keys = {
      "geometry.files",  "geometry.curve_names", "geometry.join_tolerance", "geometry.corner_angle", "geometry.hull",
      "geometry.curves", "geometry.heal",        "geometry.projection",     "geometry.region_names",
  };
  return keys;
}

const std::vector<std::string>& spacing_keys() {
  static const std::vector<std::string> keys = {
      "spacing.field",
      "spacing.expression",
      "spacing.file",
      "spacing.array",
      "spacing.scale",
      "spacing.relax_scale",
      "spacing.gradation",
      "spacing.rows_in_gap",
      "spacing.curvature_angle",
      "spacing.background_tolerance",
      "spacing.background_min_side",
      "spacing.background_boundary_min_side",
      "spacing.h1",
      "spacing.h2",
      "spacing.angle",
      "spacing.m11",
      "spacing.m12",
      "spacing.m22",
      "spacing.sol",
      "spacing.function",
      "spacing.complexity",
      "spacing.hmin",
      "spacing.hmax",
      "spacing.max_anisotropy",
      "spacing.metric_gradation",
      "spacing.hessian_step",
      "spacing.norm",
      "spacing.size",
  };
  return keys;
}

const std::vector<std::string>& boundary_keys() {
  static const std::vector<std::string> keys = {
      "boundary.nodes",
  };
  return keys;
}

const std::vector<std::string>& init_keys() {
  static const std::vector<std::string> keys = {
      "init.method",        "init.seed",           "init.total",         "init.density",
      "init.density_where", "init.lattice_levels", "init.hybrid_spread", "init.file",
  };
  return keys;
}

const std::vector<std::string>& simulation_keys() {
  static const std::vector<std::string> keys = {
      "simulation.iterations",
      "simulation.stop",
      "simulation.stop_aspect",
      "simulation.stop_angle",
      "simulation.stop_every",
      "simulation.stop_window",
      "simulation.stop_min",
      "simulation.stop_from_event",
      "simulation.metric_anneal",
      "simulation.dt_initial",
      "simulation.dt_initial.structured",
      "simulation.dt_initial.random",
      "simulation.cutoff",
      "simulation.lj_a",
      "simulation.device",
      "simulation.precision",
      "simulation.r0_rule",
      "simulation.stability_factor",
      "simulation.momentum",
      "simulation.momentum_mix",
      "simulation.verlet_skin",
  };
  return keys;
}

const std::vector<std::string>& population_keys() {
  static const std::vector<std::string> keys = {
      "population.enabled",        "population.every",  "population.start",          "population.stop",
      "population.insert",         "population.merge",  "population.remove_valence", "population.boundary",
      "population.boundary_split", "population.settle", "population.settle_events",
  };
  return keys;
}

const std::vector<std::string>& cleanup_keys() {
  static const std::vector<std::string> keys = {
      "cleanup.enabled",    "cleanup.min_angle",      "cleanup.iterations",
      "cleanup.topology",   "cleanup.split_boundary", "cleanup.trials_per_triangle",
      "cleanup.min_trials", "cleanup.settle",         "cleanup.sharp_corners",
      "cleanup.polish",     "cleanup.threads",        "cleanup.small_strip_vertices",
  };
  return keys;
}

const std::vector<std::string>& output_keys() {
  static const std::vector<std::string> keys = {
      "output.formats",         "output.tree_overlay",    "output.views", "output.color_by",
      "output.spacing_picture", "output.open_boundaries", "output.walls",
  };
  return keys;
}

const std::vector<std::string>& boundary_layer_keys() {
  static const std::vector<std::string> keys = {
      "boundary_layer.curves",    "boundary_layer.first_height",     "boundary_layer.y_plus",
      "boundary_layer.reynolds",  "boundary_layer.reference_length", "boundary_layer.growth",
      "boundary_layer.thickness", "boundary_layer.layers",           "boundary_layer.elements",
  };
  return keys;
}

const std::vector<std::string>& farfield_keys() {
  static const std::vector<std::string> keys = {
      "farfield.shape",
      "farfield.size",
      "farfield.cavities",
  };
  return keys;
}

const std::vector<std::string>& refine_keys() {
  static const std::vector<std::string> keys = {
      "refine.shape",  "refine.size",   "refine.box",    "refine.centre",
      "refine.radius", "refine.points", "refine.region", "refine.point",
  };
  return keys;
}

// periodic.rotate is an inline table whose keys (center, angle_deg) app/config/case_periodic.cpp checks.
const std::vector<std::string>& periodic_keys() {
  static const std::vector<std::string> keys = {"periodic.curves", "periodic.translate", "periodic.rotate"};
  return keys;
}

const std::vector<std::string>& motion_keys() {
  static const std::vector<std::string> keys = {
      "motion.curves", "motion.rotate",     "motion.pivot", "motion.translate",
      "motion.steps",  "motion.iterations", "motion.blend",
  };
  return keys;
}

}  // namespace

bool CaseConfig::Output::wants(const std::string& format) const {
  return std::find(formats.begin(), formats.end(), format) != formats.end();
}

std::vector<std::string> wall_curves(const CaseConfig& config) {
  std::vector<std::string> walls = config.output.walls;
  for (const CaseConfig::BoundaryLayer& layer : config.boundary_layers)
    walls.insert(walls.end(), layer.curves.begin(), layer.curves.end());
  return walls;
}

const std::vector<std::string>& CaseConfig::Output::format_names() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> n = mesh_format_names();
    n.emplace_back("png");
    n.emplace_back("svg");
    return n;
  }();
  return names;
}

const std::vector<std::string>& case_file_keys() {
  static const std::vector<std::string> keys = [] {
    std::vector<std::string> all;
    for (const auto* section :
         {&top_level_keys(), &geometry_keys(), &spacing_keys(), &boundary_keys(), &init_keys(), &simulation_keys(),
          &population_keys(), &cleanup_keys(), &output_keys(), &boundary_layer_keys(), &farfield_keys(), &refine_keys(),
          &motion_keys(), &periodic_keys()}) {
      all.insert(all.end(), section->begin(), section->end());
    }
    return all;
  }();
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
    throw InputError(
        fmt::format("{}:{}:{}: {}", source.string(), e.source().begin.line, e.source().begin.column, e.description()));
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
  return parse_case_text(read_input_file(case_file, InputKind::Case), case_file, overrides);
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
  c.geometry_alone = true;
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
