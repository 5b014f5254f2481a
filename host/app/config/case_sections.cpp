// Case files, section by section: each key of [geometry], [boundary], [spacing], [init], [simulation],
// [population], [cleanup] and [output] checked and put into CaseConfig (app/config/case_file.cpp parses the
// file, applies the overrides and checks the key names first).
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <map>
#include <regex>
#include <set>
#include <fmt/ranges.h>

#include "app/config/case_reader.hpp"
#include "core/input_file.hpp"
#include "init/warm_points.hpp"
#include "io/mixed_mesh.hpp"

namespace pdmesh::case_detail {

namespace {

// A loop, not std::regex: libstdc++'s matcher recurses once per character, so a long name would
// overflow the stack.
bool is_plain_name(const std::string& s) {
  return !s.empty() && std::all_of(s.begin(), s.end(), [](char ch) {
    return (ch >= 'A' && ch <= 'Z') || (ch >= 'a' && ch <= 'z') || (ch >= '0' && ch <= '9') || ch == '_' || ch == '.' ||
           ch == '+' || ch == '-';
  });
}

// geometry.region_names = { 1 = "steel", "2.5" = "copper" }: the keys are the attributes (a .poly's
// regional attributes, a mesh file's regions), the values plain names that the writers use for them.
void read_region_names(const Reader& r, const toml::node& n, CaseConfig& c) {
  const std::string key = "geometry.region_names";
  if (!n.is_table()) r.fail(key, &n, fmt::format("{} must be a table of attribute = \"name\"", key));
  std::map<double, CaseConfig::Geometry::RegionName> names;
  std::set<std::string> used;
  for (const auto& [k, v] : *n.as_table()) {
    const std::string text(k.str());
    char* end = nullptr;
    const double a = std::strtod(text.c_str(), &end);
    if (text.empty() || end != text.c_str() + text.size() || !std::isfinite(a) || a == 0.0)
      r.fail_at_key(
          key, k, fmt::format("{}: '{}' is not a regional attribute (a number other than 0)", key, quote_input(text)));
    const std::string name = r.string(key + "." + text, v);
    if (!is_plain_name(name) || name == kCoreRegion || name == kLayerRegion || region_attribute(name))
      r.fail(key, &v,
             fmt::format("{}: '{}' is not a plain name (letters, digits, _ . + -; not domain, boundary_layer "
                         "or region_<number>)",
                         key, quote_input(name)));
    if (!used.insert(name).second) r.fail(key, &v, fmt::format("{}: '{}' names two attributes", key, name));
    if (names.count(a) != 0) r.fail(key, &v, fmt::format("{}: attribute {} is named twice", key, a));
    names[a] = {a, name, fmt::format("{}:{}", r.file(), v.source().begin.line)};
  }
  c.geometry.region_names.clear();
  for (auto& [a, entry] : names) c.geometry.region_names.push_back(std::move(entry));
}

void read_geometry_section(const Reader& r, const toml::table& root, CaseConfig& c) {
  const toml::node* files = find(root, "geometry", "files");
  if (!c.geometry.given_curves.empty()) {
    // Curves given in memory (case_for_curves) are the geometry; files would be a second one.
    if (files != nullptr)
      r.fail("geometry.files", files, "geometry.files cannot be set: the geometry is given as curves");
  } else if (files == nullptr && !r.partial()) {
    throw InputError(fmt::format("{}: geometry.files is required (the geometry files to mesh)", r.file()));
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
               fmt::format("geometry.curve_names: '{}' is not a plain name (letters, digits, _ . + -)",
                           quote_input(name)));
      }
    }
  }
  if (const toml::node* n = find(root, "geometry", "region_names")) read_region_names(r, *n, c);
  if (const toml::node* n = find(root, "geometry", "join_tolerance")) {
    // A fraction of the extents' diagonal: checked here so that a bad value is reported at its line,
    // not later by build_geometry without the key or the file.
    const double t = r.number("geometry.join_tolerance", *n);
    if (!(t > 0 && t < 1)) {
      r.fail("geometry.join_tolerance", n, fmt::format("geometry.join_tolerance must be in (0, 1), got {}", t));
    }
    c.geometry.join_tolerance = t;
  }
  if (const toml::node* n = find(root, "geometry", "corner_angle")) {
    const double a = r.number("geometry.corner_angle", *n);
    if (!(a > 0 && a < 180)) {
      r.fail("geometry.corner_angle", n, fmt::format("geometry.corner_angle must be in (0, 180) degrees, got {}", a));
    }
    c.geometry.corner_angle = a;
  }
  if (const toml::node* n = find(root, "geometry", "hull")) {
    c.geometry.hull = r.boolean("geometry.hull", *n) ? PolyHull::On : PolyHull::Off;
  }
  if (const toml::node* n = find(root, "geometry", "heal")) c.geometry.heal = r.boolean("geometry.heal", *n);
  if (const toml::node* n = find(root, "geometry", "curves")) {
    c.geometry.curves =
        choose<CurveKind>(r, "geometry.curves", *n, {{"polyline", CurveKind::Polyline}, {"smooth", CurveKind::Smooth}});
  }
  if (const toml::node* n = find(root, "geometry", "projection")) {
    c.geometry.projection =
        choose<ProjectionKind>(r, "geometry.projection", *n,
                               {{"none", ProjectionKind::None}, {"equirectangular", ProjectionKind::Equirectangular}});
  }
}

void read_boundary_section(const Reader& r, const toml::table& root, CaseConfig& c) {
  if (const toml::node* n = find(root, "boundary", "nodes")) {
    c.boundary.nodes = choose<BoundaryNodeRule>(
        r, "boundary.nodes", *n, {{"input", BoundaryNodeRule::Input}, {"spacing", BoundaryNodeRule::Spacing}});
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
    const std::string ext = lower_extension(fs::path(f));
    // .mesh (Medit, with its .sol) is metric data only: read_metric_keys refuses it for other fields.
    if (ext != ".vtu" && ext != ".msh" && ext != ".mesh") {
      r.fail("spacing.file", file,
             fmt::format("spacing.file '{}' must be a .vtu or .msh triangle mesh", quote_input(f)));
    }
    c.spacing.file = r.resolve("spacing.file", f);
  }
  if (array != nullptr && array->is_array()) {
    // Several arrays (spacing.field = "hessian" with a file; check_metric_keys refuses the rest).
    for (const toml::node& n : *array->as_array()) {
      const std::string name = r.string("spacing.array", n);
      if (name.empty()) r.fail("spacing.array", &n, "spacing.array must not hold an empty name");
      if (std::find(c.spacing.arrays.begin(), c.spacing.arrays.end(), name) != c.spacing.arrays.end())
        r.fail("spacing.array", &n, fmt::format("spacing.array names '{}' twice", quote_input(name)));
      c.spacing.arrays.push_back(name);
    }
    if (c.spacing.arrays.empty()) r.fail("spacing.array", array, "spacing.array must not be an empty list");
    c.spacing.array = c.spacing.arrays.front();
  } else if (array != nullptr) {
    c.spacing.array = r.string("spacing.array", *array);
    if (c.spacing.array.empty()) r.fail("spacing.array", array, "spacing.array must not be empty");
  }
  // An expression or a file alone selects its field; naming kinds contradictorily is an error.
  if (field != nullptr) {
    c.spacing.field = choose<SpacingKind>(r, "spacing.field", *field,
                                          {{"boundary", SpacingKind::Boundary},
                                           {"expression", SpacingKind::Expression},
                                           {"mesh", SpacingKind::Mesh},
                                           {"metric", SpacingKind::Metric},
                                           {"hessian", SpacingKind::Hessian}});
  }
  read_metric_values(r, root, c);
  if (r.partial()) return;  // the rest is how the keys agree: the whole configuration decides
  if (field == nullptr) {
    if (expression != nullptr && file != nullptr)
      r.fail("spacing.file", file, "spacing.expression and spacing.file are both set; choose one with spacing.field");
    c.spacing.field = expression != nullptr ? SpacingKind::Expression
                      : file != nullptr     ? SpacingKind::Mesh
                                            : SpacingKind::Boundary;
  }
  const char* name = spacing_kind_name(c.spacing.field);
  check_metric_keys(r, root, c, file, array);
  if (c.spacing.field == SpacingKind::Expression && c.spacing.expression.empty()) {
    r.fail("spacing.field", field, "spacing.field is 'expression' but spacing.expression is missing or empty");
  }
  if (c.spacing.field == SpacingKind::Mesh && file == nullptr) {
    r.fail("spacing.field", field,
           "spacing.field is 'mesh' but spacing.file (a .vtu or .msh background mesh) is missing");
  }
  if (c.spacing.field != SpacingKind::Expression && expression != nullptr) {
    r.fail("spacing.expression", expression, fmt::format("spacing.expression is set but spacing.field is '{}'", name));
  }
  if (c.spacing.field != SpacingKind::Mesh && !c.spacing.metric() && file != nullptr) {
    r.fail("spacing.file", file, fmt::format("spacing.file is set but spacing.field is '{}'", name));
  }
  if (c.spacing.field != SpacingKind::Mesh && !c.spacing.metric() && array != nullptr) {
    r.fail("spacing.array", array, fmt::format("spacing.array is set but spacing.field is '{}'", name));
  }
  if (const toml::node* n = find(root, "spacing", "scale")) c.spacing.scale = r.positive("spacing.scale", *n);
  if (const toml::node* n = find(root, "spacing", "relax_scale")) {
    c.spacing.relax_scale = r.number("spacing.relax_scale", *n);
    // Beyond these the lattice would no longer be near the field at all.
    if (!(c.spacing.relax_scale >= 0.5 && c.spacing.relax_scale <= 2.0))
      r.fail("spacing.relax_scale", n,
             fmt::format("spacing.relax_scale must be in [0.5, 2], got {}", c.spacing.relax_scale));
  }
  if (const toml::node* n = find(root, "spacing", "gradation")) {
    c.spacing.gradation = r.number("spacing.gradation", *n);
    if (!(c.spacing.gradation >= 0.0 && c.spacing.gradation <= 10.0))
      r.fail("spacing.gradation", n,
             fmt::format("spacing.gradation must be in [0, 10] (0 = off), got {}", c.spacing.gradation));
  }
  if (const toml::node* n = find(root, "spacing", "rows_in_gap")) {
    c.spacing.rows_in_gap = r.number("spacing.rows_in_gap", *n);
    if (!(c.spacing.rows_in_gap == 0.0 || (c.spacing.rows_in_gap >= 1.0 && c.spacing.rows_in_gap <= 100.0)))
      r.fail("spacing.rows_in_gap", n,
             fmt::format("spacing.rows_in_gap must be 0 (off) or in [1, 100], got {}", c.spacing.rows_in_gap));
  }
  // The background quadtree's resolution: fractions and a tolerance in (0, 1].
  const auto fraction = [&](const char* name, double& value) {
    const std::string key = std::string("spacing.") + name;
    if (const toml::node* n = find(root, "spacing", name)) {
      value = r.number(key, *n);
      if (!(value > 0.0 && value <= 1.0)) r.fail(key, n, fmt::format("{} must be in (0, 1], got {}", key, value));
    }
  };
  fraction("background_tolerance", c.spacing.background_tolerance);
  fraction("background_min_side", c.spacing.background_min_side);
  fraction("background_boundary_min_side", c.spacing.background_boundary_min_side);
  if (const toml::node* n = find(root, "spacing", "curvature_angle")) {
    c.spacing.curvature_angle = r.number("spacing.curvature_angle", *n);
    if (!(c.spacing.curvature_angle >= 0.0 && c.spacing.curvature_angle <= 90.0))
      r.fail("spacing.curvature_angle", n,
             fmt::format("spacing.curvature_angle must be in [0, 90] degrees (0 = off), got {}",
                         c.spacing.curvature_angle));
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
                                       {{"structured", InitMethod::Structured},
                                        {"random", InitMethod::Random},
                                        {"hexagonal", InitMethod::Hexagonal},
                                        {"hybrid", InitMethod::Hybrid}});
  }
  if (const toml::node* n = find(root, "init", "seed")) c.init.seed = non_negative(r, "init.seed", *n);
  if (const toml::node* n = find(root, "init", "total")) c.init.total = non_negative(r, "init.total", *n);
  if (const toml::node* n = find(root, "init", "density")) {
    const double v = r.number("init.density", *n);
    if (!(v == 0.0 || (v >= 0.5 && v <= 2.0)))
      r.fail("init.density", n, fmt::format("init.density must be 0 or in [0.5, 2], got {}", v));
    c.init.density = v;
  }
  if (const toml::node* n = find(root, "init", "density_where")) {
    c.init.density_where = choose<DensityWhere>(r, "init.density_where", *n,
                                                {{"inside", DensityWhere::Inside}, {"flat", DensityWhere::Flat}});
  }
  if (const toml::node* n = find(root, "init", "lattice_levels")) {
    const std::int64_t v = r.integer("init.lattice_levels", *n);
    if (v < 0 || v > kMaxLatticeLevels)
      r.fail("init.lattice_levels", n,
             fmt::format("init.lattice_levels must be 0 or in [1, {}], got {}", kMaxLatticeLevels, v));
    c.init.lattice_levels = static_cast<int>(v);
  }
  if (const toml::node* n = find(root, "init", "hybrid_spread")) {
    const double v = r.number("init.hybrid_spread", *n);
    if (!(v >= 0.0 && v <= 1.0))
      r.fail("init.hybrid_spread", n, fmt::format("init.hybrid_spread must be in [0, 1], got {}", v));
    c.init.hybrid_spread = v;
  }
  if (const toml::node* n = find(root, "init", "file")) {
    const std::string f = r.string("init.file", *n);
    const std::string ext = lower_extension(fs::path(f));
    if (!is_warm_points_extension(ext))
      r.fail("init.file", n,
             fmt::format("init.file '{}' must be a .nodes, .msh, .vtu, .su2, .mesh or .ele file", quote_input(f)));
    c.init.file = r.resolve("init.file", f);
  }
}

bool valid_device(const std::string& d) {
  static const std::regex device("auto|host|opencl|opencl:[0-9]+:[0-9]+");
  // Bounded first: std::regex recurses once per character.
  return d.size() <= 64 && std::regex_match(d, device);
}

void read_simulation_section(const Reader& r, const toml::table& root, CaseConfig& c) {
  auto& s = c.simulation;
  if (const toml::node* n = find(root, "simulation", "iterations")) {
    const std::int64_t v = r.integer("simulation.iterations", *n);
    if (v < 0) r.fail("simulation.iterations", n, fmt::format("simulation.iterations must be >= 0, got {}", v));
    s.iterations = v;
  }
  if (const toml::node* n = find(root, "simulation", "stop")) {
    s.stop = choose<StopRule>(r, "simulation.stop", *n,
                              {{"converged", StopRule::Converged}, {"iterations", StopRule::Iterations}});
  }
  for (auto [key, out, hi] : {std::tuple{"stop_aspect", &s.stop_aspect, 0.1}, {"stop_angle", &s.stop_angle, 10.0}})
    if (const toml::node* n = find(root, "simulation", key)) {
      const std::string name = std::string("simulation.") + key;
      *out = r.number(name, *n);
      if (!(*out >= 0.0 && *out <= hi)) r.fail(name, n, fmt::format("{} must be in [0, {}], got {}", name, hi, *out));
    }
  for (auto [key, out, lo] :
       {std::tuple{"stop_every", &s.stop_every, 1}, {"stop_window", &s.stop_window, 1}, {"stop_min", &s.stop_min, 0}})
    if (const toml::node* n = find(root, "simulation", key)) {
      const std::string name = std::string("simulation.") + key;
      const std::int64_t v = r.integer(name, *n);
      if (v < lo || v > 1000000) r.fail(name, n, fmt::format("{} must be in [{}, 1000000], got {}", name, lo, v));
      *out = static_cast<int>(v);
    }
  if (const toml::node* n = find(root, "simulation", "stop_from_event"))
    s.stop_from_event = r.boolean("simulation.stop_from_event", *n);
  if (const toml::node* n = find(root, "simulation", "metric_anneal")) {
    s.metric_anneal = r.number("simulation.metric_anneal", *n);
    if (!(s.metric_anneal >= 0.5 && s.metric_anneal <= 1.0))
      r.fail("simulation.metric_anneal", n,
             fmt::format("simulation.metric_anneal must be in [0.5, 1], got {}", s.metric_anneal));
  }
  if (s.stop_window % s.stop_every != 0) {
    const toml::node* n = find(root, "simulation", "stop_window");
    if (!n) n = find(root, "simulation", "stop_every");
    r.fail("simulation.stop_window", n,
           fmt::format("simulation.stop_window must be a multiple of simulation.stop_every ({}), got {}", s.stop_every,
                       s.stop_window));
  }
  if (const toml::node* n = find(root, "simulation", "dt_initial")) {
    // "auto": the automatic rule (default_dt_initial), also where the preset sets a step.
    const auto step = [&r](const std::string& key, const toml::node& d) -> std::optional<double> {
      if (d.is_string() && d.as_string()->get() == "auto") return std::nullopt;
      if (d.is_string())
        r.fail(key, &d, fmt::format("{} must be a number > 0 or \"auto\", got '{}'", key, d.as_string()->get()));
      return r.positive(key, d);
    };
    if (n->is_table()) {
      const toml::table& per = *n->as_table();
      if (const toml::node* d = per.get("structured")) s.dt_structured = step("simulation.dt_initial.structured", *d);
      if (const toml::node* d = per.get("random")) s.dt_random = step("simulation.dt_initial.random", *d);
    } else if (n->is_integer() || n->is_floating_point() || n->is_string()) {
      s.dt_structured = s.dt_random = step("simulation.dt_initial", *n);
    } else {
      r.wrong_type("simulation.dt_initial", *n, "a number, \"auto\" or a table { structured = ..., random = ... }");
    }
  }
  if (const toml::node* n = find(root, "simulation", "cutoff")) s.cutoff = r.positive("simulation.cutoff", *n);
  if (const toml::node* n = find(root, "simulation", "lj_a")) s.lj_a = r.positive("simulation.lj_a", *n);
  if (const toml::node* n = find(root, "simulation", "device")) {
    s.device = r.string("simulation.device", *n);
    if (!valid_device(s.device)) {
      r.fail(
          "simulation.device", n,
          fmt::format("simulation.device must be auto, host, opencl or opencl:P:D, got '{}'", quote_input(s.device)));
    }
  }
  if (const toml::node* n = find(root, "simulation", "precision")) {
    s.precision =
        choose<Precision>(r, "simulation.precision", *n,
                          {{"double", Precision::Double}, {"float", Precision::Float}, {"auto", Precision::Auto}});
  }
  if (const toml::node* n = find(root, "simulation", "stability_factor")) {
    s.stability_factor = r.number("simulation.stability_factor", *n);
    if (!(s.stability_factor >= 0.0 && s.stability_factor <= 1.0)) {
      r.fail("simulation.stability_factor", n,
             fmt::format("simulation.stability_factor must be in [0, 1] (0 = the thesis' time step), got {}",
                         s.stability_factor));
    }
  }
  if (const toml::node* n = find(root, "simulation", "momentum")) {
    s.momentum = r.number("simulation.momentum", *n);
    if (!(s.momentum >= 0.0 && s.momentum < 1.0)) {
      r.fail("simulation.momentum", n,
             fmt::format("simulation.momentum must be in [0, 1) (0 = plain gradient descent), got {}", s.momentum));
    }
  }
  if (const toml::node* n = find(root, "simulation", "momentum_mix")) {
    s.momentum_mix = r.number("simulation.momentum_mix", *n);
    if (!(s.momentum_mix >= 0.0 && s.momentum_mix < 1.0)) {
      r.fail("simulation.momentum_mix", n,
             fmt::format("simulation.momentum_mix must be in [0, 1) (0 = the plain heavy-ball move), got {}",
                         s.momentum_mix));
    }
  }
  if (const toml::node* n = find(root, "simulation", "verlet_skin")) {
    // "auto": auto_verlet_skin (sim/verlet_skin.hpp), the default.
    if (n->is_string() && n->as_string()->get() == "auto") {
      s.verlet_skin.reset();
    } else if (n->is_string()) {
      r.fail("simulation.verlet_skin", n,
             fmt::format("simulation.verlet_skin must be a number in [0, 4] or \"auto\", got '{}'",
                         quote_input(n->as_string()->get())));
    } else {
      const double v = r.number("simulation.verlet_skin", *n);
      if (!(v >= 0.0 && v <= 4.0))
        r.fail("simulation.verlet_skin", n,
               fmt::format("simulation.verlet_skin must be a number in [0, 4] or \"auto\", got {}", v));
      s.verlet_skin = v;
    }
  }
  if (const toml::node* n = find(root, "simulation", "r0_rule")) {
    s.r0_any_direction =
        choose<bool>(r, "simulation.r0_rule", *n, {{"force_direction", false}, {"any_direction", true}});
  }
}

// A threshold given as one number (constant over the run) or [first, last] (ramped from the first
// event to the last), each in (lo, hi).
PopulationRamp read_ramp(const Reader& r, const std::string& key, const toml::node& n, double lo, double hi) {
  PopulationRamp ramp;
  if (n.is_array()) {
    const toml::array& a = *n.as_array();
    if (a.size() != 2)
      r.fail(key, &n, fmt::format("{} must be a number or [first, last], got {} numbers", key, a.size()));
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
      r.fail("population.stop", n,
             fmt::format("population.stop must be in (0, 1] (a fraction of the run), got {}", p.stop));
  }
  // An equilateral lattice has circumradius q / sqrt(3) = 0.577 q: insert must stay above it.
  if (const toml::node* n = find(root, "population", "insert"))
    p.insert = read_ramp(r, "population.insert", *n, 0.6, 3.0);
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
  if (const toml::node* n = find(root, "cleanup", "trials_per_triangle")) {
    k.trials_per_triangle = r.number("cleanup.trials_per_triangle", *n);
    if (!(k.trials_per_triangle >= 0.0 && k.trials_per_triangle <= 100.0))
      r.fail("cleanup.trials_per_triangle", n,
             fmt::format("cleanup.trials_per_triangle must be in [0, 100], got {}", k.trials_per_triangle));
  }
  if (const toml::node* n = find(root, "cleanup", "min_trials")) {
    k.min_trials = r.integer("cleanup.min_trials", *n);
    if (k.min_trials < 0 || k.min_trials > 1000000000)
      r.fail("cleanup.min_trials", n, fmt::format("cleanup.min_trials must be in 0..1000000000, got {}", k.min_trials));
  }
  if (const toml::node* n = find(root, "cleanup", "settle")) {
    k.settle = r.number("cleanup.settle", *n);
    if (!(k.settle >= 0.0 && k.settle <= 0.01))
      r.fail("cleanup.settle", n, fmt::format("cleanup.settle must be in [0, 0.01], got {}", k.settle));
  }
  if (const toml::node* n = find(root, "cleanup", "sharp_corners"))
    k.sharp_corners = r.boolean("cleanup.sharp_corners", *n);
  if (const toml::node* n = find(root, "cleanup", "polish")) {
    k.polish = r.integer("cleanup.polish", *n);
    if (k.polish < 0 || k.polish > 1000)
      r.fail("cleanup.polish", n, fmt::format("cleanup.polish must be in 0..1000, got {}", k.polish));
  }
  if (const toml::node* n = find(root, "cleanup", "threads")) {
    k.threads = r.integer("cleanup.threads", *n);
    if (k.threads < 0 || k.threads > 256)
      r.fail("cleanup.threads", n, fmt::format("cleanup.threads must be in 0..256, got {}", k.threads));
  }
  if (const toml::node* n = find(root, "cleanup", "small_strip_vertices")) {
    k.small_strip_vertices = r.integer("cleanup.small_strip_vertices", *n);
    if (k.small_strip_vertices < 0 || k.small_strip_vertices > 1000000)
      r.fail("cleanup.small_strip_vertices", n,
             fmt::format("cleanup.small_strip_vertices must be in 0..1000000, got {}", k.small_strip_vertices));
  }
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
        r.fail(sub, &n,
               fmt::format("{} '{}' must be a plain name (letters, digits, _ . + -)", sub, quote_input(v.name)));
      }
    } else if (k == "window") {
      window = &n;
    } else {
      const std::string hint = edit_distance(k.str(), "name") <= 2 ? "name" : "window";
      r.fail_at_key(sub, k, fmt::format("unknown key '{}'; did you mean '{}.{}'?", sub, quote_input(key), hint));
    }
  }
  if (window == nullptr) r.fail(key, &entry, fmt::format("{} needs window = [x0, y0, x1, y1]", key));
  const toml::array& a = r.array(key + ".window", *window);
  if (a.size() != 4)
    r.fail(key + ".window", window, fmt::format("{}.window must have 4 numbers, got {}", key, a.size()));
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
    const auto& known = CaseConfig::Output::format_names();
    for (const std::string& f : c.output.formats) {
      if (std::find(known.begin(), known.end(), f) == known.end()) {
        r.fail("output.formats", n,
               fmt::format("output.formats: unknown format '{}'; valid formats are {}", quote_input(f),
                           fmt::join(known, ", ")));
      }
    }
    if (c.output.wants("msh") && c.output.wants("msh22"))
      r.fail("output.formats", n, "output.formats: 'msh' and 'msh22' both write mesh.msh; ask for one of them");
  }
  if (const toml::node* n = find(root, "output", "color_by")) {
    c.output.color_by = choose<std::string>(r, "output.color_by", *n,
                                            {{"none", "none"},
                                             {"min_angle", "min_angle"},
                                             {"max_angle", "max_angle"},
                                             {"aspect_ratio", "aspect_ratio"},
                                             {"skewness", "skewness"},
                                             {"condition_number", "condition_number"},
                                             {"min_jacobian", "min_jacobian"},
                                             {"region", "region"}});
  }
  if (const toml::node* n = find(root, "output", "open_boundaries"))
    c.output.open_boundaries = r.strings("output.open_boundaries", *n);
  if (const toml::node* n = find(root, "output", "walls")) c.output.walls = r.strings("output.walls", *n);
  if (const toml::node* n = find(root, "output", "tree_overlay"))
    c.output.tree_overlay = r.boolean("output.tree_overlay", *n);
  if (const toml::node* n = find(root, "output", "spacing_picture"))
    c.output.spacing_picture = r.boolean("output.spacing_picture", *n);
  if (const toml::node* n = find(root, "output", "views")) {
    const toml::array& a = r.array("output.views", *n);
    for (std::size_t i = 0; i < a.size(); ++i) {
      ViewWindow v = read_view(r, *a.get(i), i);
      for (const ViewWindow& earlier : c.output.views) {
        if (earlier.name == v.name) {
          r.fail(fmt::format("output.views[{}]", i), a.get(i),
                 fmt::format("view name '{}' is used twice", quote_input(v.name)));
        }
      }
      c.output.views.push_back(std::move(v));
    }
  }
}

}  // namespace

void read_case_sections(const Reader& r, const toml::table& root, CaseConfig& c) {
  read_geometry_section(r, root, c);
  read_spacing_section(r, root, c);
  read_boundary_section(r, root, c);
  read_init_section(r, root, c);
  read_simulation_section(r, root, c);
  read_population_section(r, root, c);
  read_cleanup_section(r, root, c);
  read_output_section(r, root, c);
  read_boundary_layer_sections(r, root, c);
  read_size_sections(r, root, c);
  read_motion_section(r, root, c);
  read_periodic_sections(r, root, c);
  // The preset set relax_scale for the structured fill; a case that names another fill and not the
  // key gets that fill's value.
  if (find(root, "spacing", "relax_scale") == nullptr)
    c.spacing.relax_scale = preset_relax_scale(c.preset, c.init.method);
  // Likewise stop_angle, set for an isotropic run: a metric case without the key gets the metric value.
  if (find(root, "simulation", "stop_angle") == nullptr)
    c.simulation.stop_angle = preset_stop_angle(c.preset, c.spacing.metric());
  // And the drift tolerance, the momentum's steering, population control's stop and the structured
  // start's step, set for an isotropic run too.
  if (find(root, "simulation", "stop_aspect") == nullptr)
    c.simulation.stop_aspect = preset_stop_aspect(c.preset, c.spacing.metric());
  if (find(root, "simulation", "momentum_mix") == nullptr)
    c.simulation.momentum_mix = preset_momentum_mix(c.preset, c.spacing.metric());
  if (find(root, "simulation", "stop_from_event") == nullptr)
    c.simulation.stop_from_event = preset_stop_from_event(c.preset, c.spacing.metric(), !c.boundary_layers.empty());
  if (find(root, "population", "stop") == nullptr)
    c.population.stop = preset_population_stop(c.preset, c.spacing.metric());
  // A dt_initial table that sets only the random start's step leaves the structured one to the preset.
  const toml::node* dt = find(root, "simulation", "dt_initial");
  if (dt == nullptr || (dt->is_table() && dt->as_table()->get("structured") == nullptr))
    c.simulation.dt_structured = preset_dt_structured(c.preset, c.spacing.metric());
}

}  // namespace pdmesh::case_detail
