// Checkpoint location and case identity for `pdmesh mesh --resume`.
#include "app/pipeline/resume.hpp"

#include <cstdint>
#include <fmt/format.h>
#include <fmt/ranges.h>

#include "core/errors.hpp"
#include "io/text_file.hpp"

namespace pdmesh {

namespace fs = std::filesystem;

namespace {

// The (key, value) lines that identify a case in its checkpoint.
using Identity = std::vector<std::pair<std::string, std::string>>;

// FNV-1a, 64 bits: identifies a geometry file's content (not a security measure).
std::uint64_t fnv1a64(const std::string& bytes) {
  std::uint64_t h = 14695981039346656037ull;
  for (unsigned char c : bytes) {
    h ^= c;
    h *= 1099511628211ull;
  }
  return h;
}

std::string find_value(const std::vector<std::pair<std::string, std::string>>& keys, const std::string& key,
                       bool& found) {
  for (const auto& [k, v] : keys)
    if (k == key) {
      found = true;
      return v;
    }
  found = false;
  return {};
}

// The geometry files (by content), how they are joined, and the boundary-node rule.
void add_geometry_identity(const CaseConfig& config, Identity& keys) {
  for (std::size_t f = 0; f < config.geometry.files.size(); ++f) {
    const fs::path& file = config.geometry.files[f];
    const std::string content = read_text_file(file, InputKind::Geometry);
    keys.emplace_back(
        fmt::format("geometry.file.{}", f),
        fmt::format("{} ({} bytes, FNV-1a {:016x})", file.filename().string(), content.size(), fnv1a64(content)));
  }
  std::string names;
  for (const std::string& n : config.geometry.curve_names) names += (names.empty() ? "" : ",") + n;
  keys.emplace_back("geometry.curve_names", names);
  keys.emplace_back("geometry.join_tolerance", fmt::format("{}", config.geometry.join_tolerance));
  keys.emplace_back("geometry.corner_angle", fmt::format("{}", config.geometry.corner_angle));
  // Only where they differ from the thesis' rule, so that checkpoints written before these keys
  // existed keep their identity.
  if (config.geometry.curves != CurveKind::Polyline) keys.emplace_back("geometry.curves", "smooth");
  if (config.boundary.nodes != BoundaryNodeRule::Input) keys.emplace_back("boundary.nodes", "spacing");
  if (config.geometry.projection != ProjectionKind::None) keys.emplace_back("geometry.projection", "equirectangular");
}

// The spacing field's kind and the inputs it is built from.
void add_spacing_field_identity(const CaseConfig& config, Identity& keys) {
  keys.emplace_back("spacing.field", config.spacing.field == SpacingKind::Expression ? "expression"
                                     : config.spacing.field == SpacingKind::Mesh     ? "mesh"
                                     : config.spacing.field == SpacingKind::Metric   ? "metric"
                                     : config.spacing.field == SpacingKind::Hessian  ? "hessian"
                                                                                     : "boundary");
  keys.emplace_back("spacing.expression", config.spacing.expression);
  const auto file_identity = [&keys](const char* key, const std::filesystem::path& file) {
    const std::string content = read_text_file(file, InputKind::Mesh);
    keys.emplace_back(
        key, fmt::format("{} ({} bytes, FNV-1a {:016x})", file.filename().string(), content.size(), fnv1a64(content)));
  };
  // Only for a field read from a file, so that checkpoints of the other fields keep their identity.
  if (config.spacing.field == SpacingKind::Mesh || (config.spacing.metric() && !config.spacing.file.empty())) {
    file_identity("spacing.file", config.spacing.file);
    if (!config.spacing.sol.empty())
      file_identity("spacing.sol", config.spacing.sol);
    else if (config.spacing.arrays.size() > 1)
      keys.emplace_back("spacing.array", fmt::format("{}", fmt::join(config.spacing.arrays, ", ")));
    else
      keys.emplace_back("spacing.array", config.spacing.array);
  }
  // The metric keys, only for a metric field (the other fields' checkpoints keep their identity).
  if (config.spacing.metric()) {
    const auto& s = config.spacing;
    for (const auto& [key, value] : {std::pair{"spacing.h1", &s.h1},
                                     {"spacing.h2", &s.h2},
                                     {"spacing.angle", &s.angle},
                                     {"spacing.m11", &s.m11},
                                     {"spacing.m12", &s.m12},
                                     {"spacing.m22", &s.m22},
                                     {"spacing.function", &s.function}}) {
      keys.emplace_back(key, *value);
    }
    keys.emplace_back("spacing.complexity", fmt::format("{}", s.complexity));
    keys.emplace_back("spacing.hmin", fmt::format("{}", s.hmin));
    keys.emplace_back("spacing.hmax", fmt::format("{}", s.hmax));
    keys.emplace_back("spacing.max_anisotropy", fmt::format("{}", s.max_anisotropy));
    keys.emplace_back("spacing.metric_gradation", fmt::format("{}", s.metric_gradation));
    // Only when not the L2 norm, so that checkpoints of earlier Hessian runs identify the same way.
    if (s.norm != 2.0) keys.emplace_back("spacing.norm", fmt::format("{}", s.norm));
  }
}

// The far field, a uniform size and the refinement regions.
void add_region_identity(const CaseConfig& config, Identity& keys) {
  // The far field, a uniform size and refinement regions: only when set, so that checkpoints of runs
  // without them (older files too) identify the same way.
  if (config.farfield.given())
    keys.emplace_back("farfield", fmt::format("{} {}", config.farfield.shape == FarfieldShape::Box ? "box" : "circle",
                                              config.farfield.size));
  // The cavities meshed: only when asked, so that the default identifies as before.
  if (config.farfield.given() && config.farfield.cavities == FarfieldCavities::Mesh)
    keys.emplace_back("farfield.cavities", "mesh");
  if (config.spacing.size > 0.0) keys.emplace_back("spacing.size", fmt::format("{}", config.spacing.size));
  for (std::size_t k = 0; k < config.spacing.regions.size(); ++k) {
    const RefineRegion& r = config.spacing.regions[k];
    std::string points;
    for (const Vec2 p : r.points) points += fmt::format(" {} {}", p.x, p.y);
    // A subdomain's selector only for that shape, so that the other shapes identify as before.
    std::string subdomain;
    if (r.shape == RegionShape::Subdomain)
      subdomain = r.attribute ? fmt::format(" region {}", *r.attribute)
                  : r.at      ? fmt::format(" point {} {}", r.at->x, r.at->y)
                              : fmt::format(" name {}", r.region_name);
    keys.emplace_back(fmt::format("refine.{}", k),
                      fmt::format("{} {} box {} {} {} {} centre {} {} radius {} points{}{}", static_cast<int>(r.shape),
                                  r.size, r.box.lo.x, r.box.lo.y, r.box.hi.x, r.box.hi.y, r.centre.x, r.centre.y,
                                  r.radius, points, subdomain));
  }
}

// The keys of the spacing pipeline and its background.
void add_spacing_pipeline_identity(const CaseConfig& config, Identity& keys) {
  // The pipeline's keys change the field the run follows.
  keys.emplace_back("spacing.scale", fmt::format("{}", config.spacing.scale));
  // Only when not 1 (the thesis' and long's value), so that checkpoints written before the key existed
  // identify the same way.
  if (config.spacing.relax_scale != 1.0)
    keys.emplace_back("spacing.relax_scale", fmt::format("{}", config.spacing.relax_scale));
  keys.emplace_back("spacing.gradation", fmt::format("{}", config.spacing.gradation));
  keys.emplace_back("spacing.rows_in_gap", fmt::format("{}", config.spacing.rows_in_gap));
  keys.emplace_back("spacing.curvature_angle", fmt::format("{}", config.spacing.curvature_angle));
  // The background's resolution changes the field too. Only when not the thesis' (and long's) values,
  // so that checkpoints written before these keys existed identify the same way.
  const BackgroundOptions defaults;
  if (config.spacing.background_tolerance != defaults.tolerance ||
      config.spacing.background_min_side != defaults.min_side_fraction ||
      config.spacing.background_boundary_min_side != defaults.boundary_min_side_fraction) {
    keys.emplace_back("spacing.background_tolerance", fmt::format("{}", config.spacing.background_tolerance));
    keys.emplace_back("spacing.background_min_side", fmt::format("{}", config.spacing.background_min_side));
    keys.emplace_back("spacing.background_boundary_min_side",
                      fmt::format("{}", config.spacing.background_boundary_min_side));
  }
}

// The initial distribution and the simulation's parameters.
void add_simulation_identity(const CaseConfig& config, Identity& keys) {
  keys.emplace_back("init.method", to_string(config.init.method));
  keys.emplace_back("init.seed", fmt::format("{}", config.init.seed));
  keys.emplace_back("init.total", fmt::format("{}", config.init.total));
  // Named only when set, so that checkpoints of runs without it keep their identity.
  if (config.init.density != 0.0) keys.emplace_back("init.density", fmt::format("{}", config.init.density));
  if (config.init.density != 0.0 && config.init.density_where == DensityWhere::Flat)
    keys.emplace_back("init.density_where", "flat");
  if (config.init.density != 0.0 && config.init.lattice_levels != 0)
    keys.emplace_back("init.lattice_levels", fmt::format("{}", config.init.lattice_levels));
  if (config.init.method == InitMethod::Hybrid && config.init.hybrid_spread != kHybridSpread)
    keys.emplace_back("init.hybrid_spread", fmt::format("{}", config.init.hybrid_spread));
  const auto dt = config.simulation.dt_for(config.init.method);
  keys.emplace_back("simulation.dt_initial", dt ? fmt::format("{}", *dt) : std::string("auto"));
  keys.emplace_back("simulation.cutoff", fmt::format("{}", config.simulation.cutoff));
  keys.emplace_back("simulation.lj_a", fmt::format("{}", config.simulation.lj_a));
  keys.emplace_back("simulation.r0_rule", config.simulation.r0_any_direction ? "any_direction" : "force_direction");
  keys.emplace_back("simulation.stability_factor", fmt::format("{}", config.simulation.stability_factor));
  // Only when on, so that checkpoints of runs without momentum (older files too) identify the same way.
  if (config.simulation.momentum > 0.0)
    keys.emplace_back("simulation.momentum", fmt::format("{}", config.simulation.momentum));
  // Likewise the mix, which only acts with momentum.
  if (config.simulation.momentum > 0.0 && config.simulation.momentum_mix > 0.0)
    keys.emplace_back("simulation.momentum_mix", fmt::format("{}", config.simulation.momentum_mix));
}

// Population control's schedule and thresholds.
void add_population_identity(const CaseConfig& config, Identity& keys) {
  // Population control shapes the node set; its keys are named only when it is on, so that a
  // checkpoint of a run without it (older files too) identifies the same way.
  const PopulationOptions& p = config.population;
  if (p.enabled) {
    keys.emplace_back("population.enabled", "true");
    // The settle keys only when settling is on (settle > 0): with it off the schedule is the one before
    // them, and so is its identity, so that earlier checkpoints of such runs still resume.
    keys.emplace_back("population.schedule", p.settle > 0
                                                 ? fmt::format("every {} start {} stop {} settle {} {}", p.every,
                                                               p.start, p.stop, p.settle, p.settle_events)
                                                 : fmt::format("every {} start {} stop {}", p.every, p.start, p.stop));
    keys.emplace_back("population.thresholds", fmt::format("insert {} {} merge {} {} valence {} boundary {} split {}",
                                                           p.insert.first, p.insert.last, p.merge.first, p.merge.last,
                                                           p.remove_valence, p.boundary, p.boundary_split));
  }
}

}  // namespace

fs::path checkpoint_path(const fs::path& dir) { return dir / "checkpoint.pdmesh"; }

std::vector<std::pair<std::string, std::string>> case_identity(const CaseConfig& config) {
  Identity keys;
  add_geometry_identity(config, keys);
  add_spacing_field_identity(config, keys);
  add_region_identity(config, keys);
  add_spacing_pipeline_identity(config, keys);
  add_simulation_identity(config, keys);
  add_population_identity(config, keys);
  // Values are single lines (a checkpoint stores one key per line).
  for (auto& [k, v] : keys)
    for (char& c : v)
      if (c == '\n' || c == '\r') c = ' ';
  return keys;
}

Checkpoint read_checkpoint_for(const fs::path& resume, const CaseConfig& config, const GeometryTree& tree) {
  std::error_code ec;
  const fs::path file = fs::is_directory(resume, ec) ? checkpoint_path(resume) : resume;
  if (!fs::exists(file, ec))
    throw InputError(
        fmt::format("--resume {}: there is no checkpoint '{}' (a run leaves one only when it was "
                    "interrupted or failed)",
                    resume.string(), file.string()));
  Checkpoint checkpoint = read_checkpoint(file);
  const auto here = case_identity(config);
  for (const auto& [key, value] : here) {
    bool found = false;
    const std::string there = find_value(checkpoint.case_keys, key, found);
    if (!found || there != value)
      throw InputError(fmt::format("{}: the checkpoint belongs to another case: {} is '{}' there and '{}' in {}",
                                   file.string(), key, found ? there : std::string("(missing)"), value,
                                   config.source.string()));
  }
  for (const auto& [key, value] : checkpoint.case_keys) {
    bool found = false;
    find_value(here, key, found);
    if (!found)
      throw InputError(fmt::format("{}: the checkpoint belongs to another case: it has {} = '{}', {} has none",
                                   file.string(), key, value, config.source.string()));
  }
  // --iterations 0 meshes the checkpoint's nodes as they are (run_mesh).
  if (config.simulation.iterations > 0 && checkpoint.state.iterations_done > config.simulation.iterations)
    throw InputError(fmt::format("{}: the checkpoint is after {} iterations, more than --iterations {}", file.string(),
                                 checkpoint.state.iterations_done, config.simulation.iterations));
  check_checkpoint_fits(checkpoint, tree, file.string());
  // Which curves are embedded constraints is the geometry's, not the checkpoint's.
  const Geometry& g = tree.geometry();
  for (std::size_t c = 0; c < g.curves.size() && c < checkpoint.nodes.curve_nodes.size(); ++c) {
    if (!g.curves[c].constraint) continue;
    checkpoint.nodes.constraint_curves.resize(checkpoint.nodes.curve_nodes.size(), 0);
    checkpoint.nodes.constraint_curves[c] = 1;
  }
  return checkpoint;
}

}  // namespace pdmesh
