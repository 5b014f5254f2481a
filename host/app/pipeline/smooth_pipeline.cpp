// pdmesh smooth; see smooth_pipeline.hpp.
#include "app/pipeline/smooth_pipeline.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <fmt/format.h>
#include <memory>
#include <optional>
#include <unordered_map>
#include <utility>

#include "app/pipeline/mesh_pipeline.hpp"
#include "core/errors.hpp"
#include "core/input_file.hpp"
#include "core/predicates.hpp"
#include "geometry/geometry_files.hpp"
#include "init/kept_nodes.hpp"
#include "init/warm_points.hpp"
#include "io/mesh_formats.hpp"
#include "io/mesh_geometry.hpp"
#include "spacing/mesh_spacing.hpp"

namespace pdmesh {

namespace {

std::uint64_t edge_key(int a, int b) {
  if (a > b) std::swap(a, b);
  return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 32) | static_cast<std::uint32_t>(b);
}

// The mesh's edges with the number of triangles at each.
std::unordered_map<std::uint64_t, int> edge_counts(const Mesh& mesh) {
  std::unordered_map<std::uint64_t, int> count;
  count.reserve(mesh.triangles.size() * 2);
  for (const auto& t : mesh.triangles)
    for (int k = 0; k < 3; ++k) ++count[edge_key(t[k], t[(k + 1) % 3])];
  return count;
}

}  // namespace

void check_smooth_mesh(Mesh& mesh, const std::string& label) {
  std::vector<std::size_t> reoriented;
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    auto& v = mesh.triangles[t];
    for (const int i : v)
      if (i < 0 || static_cast<std::size_t>(i) >= mesh.points.size())
        throw InputError(
            fmt::format("{}: triangle {} names node {}, not one of the {} points", label, t, i, mesh.points.size()));
    if (orient2d(mesh.points[v[0]], mesh.points[v[1]], mesh.points[v[2]]) < 0.0) {
      std::swap(v[1], v[2]);
      reoriented.push_back(t);
    }
  }
  for (std::size_t i = 0; i < mesh.points.size(); ++i)
    if (!std::isfinite(mesh.points[i].x) || !std::isfinite(mesh.points[i].y))
      throw InputError(fmt::format("{}: node {} is not finite", label, mesh_node_text(mesh, static_cast<int>(i))));
  check_mesh_triangles(mesh, reoriented, label);
}

Mesh read_smooth_mesh(const std::filesystem::path& file, const std::string& label) {
  MeshReadReport report;
  Mesh mesh = read_mesh(file, report);
  check_mesh_triangles(mesh, report.reoriented, label.empty() ? file.string() : label);
  return mesh;
}

namespace {

// Per point: the mean length of its boundary edges (the edges of one triangle); 0 off the boundary.
std::vector<double> mean_boundary_edge(const Mesh& mesh) {
  std::vector<double> length(mesh.points.size(), 0.0);
  std::vector<int> count(mesh.points.size(), 0);
  for (const auto& [key, triangles] : edge_counts(mesh)) {
    if (triangles != 1) continue;
    const auto a = static_cast<std::size_t>(key >> 32);
    const auto b = static_cast<std::size_t>(key & 0xffffffffu);
    const double l = dist(mesh.points[a], mesh.points[b]);
    length[a] += l;
    length[b] += l;
    ++count[a];
    ++count[b];
  }
  for (std::size_t i = 0; i < length.size(); ++i)
    if (count[i] > 0) length[i] /= count[i];
  return length;
}

}  // namespace

std::vector<double> node_spacing(const Mesh& mesh) {
  const std::size_t n = mesh.points.size();
  // Interior: a third of the area of the triangles at the node is its share of the domain; an
  // equilateral mesh with edges h gives every node (sqrt(3) / 2) h^2.
  std::vector<double> area(n, 0.0);
  for (const auto& t : mesh.triangles) {
    const double a =
        0.5 * std::abs(cross(mesh.points[t[1]] - mesh.points[t[0]], mesh.points[t[2]] - mesh.points[t[0]]));
    for (const int v : t) area[static_cast<std::size_t>(v)] += a / 3.0;
  }
  std::vector<double> q(n, 0.0);
  for (std::size_t i = 0; i < n; ++i) q[i] = std::sqrt(2.0 * area[i] / std::sqrt(3.0));
  // Boundary: the mean length of its boundary edges.
  const std::vector<double> boundary = mean_boundary_edge(mesh);
  for (std::size_t i = 0; i < n; ++i)
    if (boundary[i] > 0.0) q[i] = boundary[i];
  return q;
}

void check_mesh_on_geometry(const Mesh& mesh, const std::string& label, const Geometry& geometry,
                            const GeometryTree& tree) {
  Box box;
  for (const Vec2 p : mesh.points) box.add(p);
  const Box& g = geometry.extents;
  if (box.hi.x < g.lo.x || box.lo.x > g.hi.x || box.hi.y < g.lo.y || box.lo.y > g.hi.y)
    throw InputError(fmt::format(
        "{}: the mesh [{}, {}] x [{}, {}] does not overlap the geometry [{}, {}] x [{}, {}]: a mesh of another "
        "geometry?",
        label, box.lo.x, box.hi.x, box.lo.y, box.hi.y, g.lo.x, g.hi.x, g.lo.y, g.hi.y));
  // Each boundary node's allowance is a share of the mean length of its boundary edges.
  const std::vector<double> boundary = mean_boundary_edge(mesh);
  const double absolute = 1e-6 * geometry.extents.diagonal();
  for (std::size_t i = 0; i < mesh.points.size(); ++i) {
    if (boundary[i] == 0.0) continue;
    const double allowed = std::max(absolute, kSmoothBoundaryTolerance * boundary[i]);
    const ClosestHit hit = tree.closest(mesh.points[i]);
    if (hit.segment >= 0 && hit.distance <= allowed) continue;
    const std::string curve =
        hit.segment >= 0 ? geometry.curves[static_cast<std::size_t>(geometry.segments[hit.segment].curve)].name : "";
    throw InputError(fmt::format(
        "{}: boundary node {} lies {:.6g} from the geometry's curves (nearest: '{}'); allowed {:.3g} ({} x the mean "
        "length of its boundary edges): a mesh of another geometry, or nodes off the curves",
        label, mesh_node_text(mesh, static_cast<int>(i)), hit.distance, curve, allowed, kSmoothBoundaryTolerance));
  }
}

std::vector<CaseOverride> smooth_overrides(SmoothField field) {
  std::vector<CaseOverride> out{
      {"preset", "\"best\"", "pdmesh smooth"},
      {"cleanup.sharp_corners", "true", "pdmesh smooth"},
      // The schedule its measurements were made with, where the case sets none.
      {.key = "population.stop",
       .value = fmt::format("{}", kSmoothPopulationStop),
       .label = "pdmesh smooth",
       .if_unset = true},
      {.key = "simulation.stop_aspect",
       .value = fmt::format("{}", kSmoothStopAspect),
       .label = "pdmesh smooth",
       .if_unset = true},
      {.key = "simulation.momentum_mix", .value = "0", .label = "pdmesh smooth", .if_unset = true},
      {.key = "simulation.dt_initial.structured", .value = "\"auto\"", .label = "pdmesh smooth", .if_unset = true},
      {.key = "simulation.stop_from_event", .value = "false", .label = "pdmesh smooth", .if_unset = true}};
  if (field != SmoothField::Mesh) return out;
  const std::string by = "pdmesh smooth (--field mesh)";
  out.push_back({"spacing.scale", fmt::format("{}", kSmoothMeshScale), by});
  out.push_back({"spacing.gradation", fmt::format("{}", kSmoothGradation), by});
  out.push_back({"spacing.rows_in_gap", "0.0", by});
  out.push_back({"spacing.curvature_angle", "0.0", by});
  return out;
}

namespace {

Geometry case_geometry(const CaseConfig& config) {
  std::vector<std::string> files;
  for (const std::filesystem::path& f : config.geometry.files) files.push_back(f.string());
  GeometryOptions options;
  options.join_tolerance = config.geometry.join_tolerance;
  options.corner_angle_deg = config.geometry.corner_angle;
  return config.geometry.given_curves.empty()
             ? read_geometry(files, config.geometry.curve_names, options,
                             {ProjectionKind::None, nullptr, {}, mesh_geometry_files()})
             : geometry_from_curves(config.geometry.given_curves, config.geometry.curve_names, options);
}

}  // namespace

double min_angle_apart_from_sharp_corners(const Mesh& mesh, double degrees) {
  const std::size_t n = mesh.points.size();
  std::vector<int> triangles(n, 0);
  for (const auto& t : mesh.triangles)
    for (const int v : t) ++triangles[static_cast<std::size_t>(v)];
  const std::vector<double> boundary = mean_boundary_edge(mesh);
  double worst = 180.0;
  for (const auto& t : mesh.triangles)
    for (int k = 0; k < 3; ++k) {
      const Vec2 a = mesh.points[t[k]], b = mesh.points[t[(k + 1) % 3]], c = mesh.points[t[(k + 2) % 3]];
      const double angle = std::atan2(std::abs(cross(b - a, c - a)), dot(b - a, c - a)) * 57.29577951308232;
      // Alone at a boundary node: the domain's angle there.
      const auto v = static_cast<std::size_t>(t[k]);
      if (boundary[v] > 0.0 && triangles[v] == 1 && angle < degrees) continue;
      worst = std::min(worst, angle);
    }
  return worst;
}

namespace {

// Keeps the input's nodes when the mesh is at the cleanup's target already (docs/smoothing.md, "A mesh
// at the target"): no simulation, and the cleanup without topology changes, so only its smoothing
// sweeps move nodes, each move kept only when it lowers neither its star's smallest angle nor raises
// its aspect-ratio sum.
void keep_if_at_target(CaseConfig& config, const Mesh& mesh, const Geometry& geometry, const GeometryTree& tree) {
  if (!config.cleanup.enabled || config.geometry.projection != ProjectionKind::None ||
      config.geometry.curves != CurveKind::Polyline || config.farfield.given())
    return;
  if (min_angle_apart_from_sharp_corners(mesh, config.cleanup.min_angle) < config.cleanup.min_angle) return;
  std::optional<KeptNodes> kept = keep_mesh_nodes(mesh, geometry, tree, 1e-6 * geometry.extents.diagonal());
  if (!kept) return;
  config.init.kept = std::make_shared<const KeptNodes>(std::move(*kept));
  config.simulation.iterations = 0;
  config.cleanup.topology = false;
  // The nodes were matched to the curves as given.
  config.geometry.heal = false;
}

}  // namespace

void make_smooth_config(CaseConfig& config, const Mesh& mesh, const std::filesystem::path& file,
                        const std::string& label, SmoothField field) {
  if (!config.boundary_layers.empty())
    throw InputError(fmt::format("{}: pdmesh smooth does not grow [[boundary_layer]]s; remove them from the case",
                                 config.source.string()));
  const Geometry geometry = case_geometry(config);
  const GeometryTree tree(geometry);
  check_mesh_on_geometry(mesh, label, geometry, tree);
  MeshFieldData data;
  data.points = mesh.points;
  data.triangles = mesh.triangles;
  data.q = node_spacing(mesh);
  data.file = label;
  data.array = "node spacing";
  auto spacing = std::make_shared<MeshSpacing>(std::move(data));
  spacing->check_covers(geometry);
  if (field == SmoothField::Mesh) {
    // The mesh's isotropic field replaces the case's, a metric one included (which would otherwise
    // still make the run a metric run).
    config.spacing.field = SpacingKind::Mesh;
    config.spacing.given = std::move(spacing);
  }
  config.init.file = file;
  keep_if_at_target(config, mesh, geometry, tree);
}

int run_smooth(CaseConfig config, const std::filesystem::path& mesh_file, SmoothField field) {
  const std::string ext = lower_extension(mesh_file);
  if (!is_warm_points_extension(ext) || ext == ".nodes")
    throw InputError(
        fmt::format("{}: not a .msh, .vtu, .su2, Medit .mesh or Triangle .ele/.node mesh", mesh_file.string()));
  const Mesh mesh = read_smooth_mesh(mesh_file);
  make_smooth_config(config, mesh, mesh_file, mesh_file.string(), field);
  return run_mesh(config);
}

}  // namespace pdmesh
