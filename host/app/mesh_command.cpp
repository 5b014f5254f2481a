// The `pdmesh mesh` pipeline: read and check inputs, check limits, initialize, write outputs.
#include "app/mesh_command.hpp"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fmt/format.h>

#include "app/exit_codes.hpp"
#include "core/errors.hpp"
#include "geometry/geometry_files.hpp"
#include "nodes/node_file.hpp"
#include "render/node_picture.hpp"

namespace pdmesh {

namespace fs = std::filesystem;

namespace {

const char* method_name(InitMethod m) { return m == InitMethod::Structured ? "structured" : "random"; }

template <class... Args>
void progress(const CaseConfig& config, fmt::format_string<Args...> format, Args&&... args) {
  if (!config.quiet) fmt::print(stderr, "{}\n", fmt::format(format, std::forward<Args>(args)...));
}

}  // namespace

MeshInputs::MeshInputs(const CaseConfig& config) {
  std::vector<std::string> files;
  for (const fs::path& f : config.geometry.files) files.push_back(f.string());
  GeometryOptions options;
  options.join_tolerance = config.geometry.join_tolerance;
  options.corner_angle_deg = config.geometry.corner_angle;
  geometry = read_geometry(files, config.geometry.curve_names, options);
  // Curve names are fields in node and mesh files; one with white space would break them later.
  for (std::size_t c = 0; c < geometry.curves.size(); ++c) {
    const std::string& name = geometry.curves[c].name;
    if (name.empty() || name.find_first_of(" \t\r\n") != std::string::npos) {
      throw InputError(fmt::format("{}:{}: curve {} name '{}' is empty or contains white space; name the curves "
                                   "with geometry.curve_names",
                                   geometry.curves[c].file, geometry.curves[c].line, c, name));
    }
  }
  tree = std::make_unique<GeometryTree>(geometry);
  if (config.spacing.field == SpacingKind::Expression) {
    spacing = std::make_unique<ExpressionSpacing>(config.spacing.expression);
  } else {
    spacing = std::make_unique<BoundarySpacing>(*tree);
  }
}

std::vector<std::string> MeshInputs::curve_names() const {
  std::vector<std::string> names;
  for (const Curve& c : geometry.curves) names.push_back(c.name);
  return names;
}

double check_node_limit(const CaseConfig& config, const MeshInputs& inputs) {
  const double estimate = estimate_node_count(*inputs.tree, *inputs.spacing);
  const auto limit = static_cast<double>(config.max_nodes);
  if (!std::isfinite(estimate) || estimate > limit) {
    throw LimitError(fmt::format("{}: the spacing field asks for about {:.0f} nodes (hexagonal-packing estimate), "
                                 "more than --max-nodes {}; coarsen the spacing or raise --max-nodes",
                                 config.source.string(), estimate, config.max_nodes));
  }
  if (config.init.total > config.max_nodes) {
    throw LimitError(fmt::format("{}: init.total = {} is more than --max-nodes {}", config.source.string(),
                                 config.init.total, config.max_nodes));
  }
  return estimate;
}

InitialDistribution make_initial(const CaseConfig& config, const MeshInputs& inputs) {
  InitOptions options;
  options.method = config.init.method;
  options.seed = config.init.seed;
  if (config.init.total > 0) options.total = static_cast<std::size_t>(config.init.total);
  return make_initial_distribution(*inputs.tree, *inputs.spacing, options);
}

void prepare_output_directory(const CaseConfig& config) {
  std::error_code ec;
  fs::create_directories(config.out_dir, ec);
  if (ec || !fs::is_directory(config.out_dir)) {
    throw InputError(fmt::format("cannot create output directory '{}': {}", config.out_dir.string(),
                                 ec ? ec.message() : std::string("a file of that name exists")));
  }
}

void write_initial_outputs(const CaseConfig& config, const MeshInputs& inputs, const InitialDistribution& initial) {
  const fs::path& dir = config.out_dir;
  write_node_file(dir / "initial.nodes", initial.nodes, inputs.curve_names());
  NodePictureOptions picture;
  picture.title = fmt::format("{} - initial distribution ({})", config.name, method_name(config.init.method));
  picture.tree_quads = config.output.tree_overlay ? &initial.tree_quads : nullptr;
  write_node_picture(dir / "initial.png", inputs.geometry, initial.nodes, picture);
  write_node_picture(dir / "initial.svg", inputs.geometry, initial.nodes, picture);
  for (const ViewWindow& view : config.output.views) {
    NodePictureOptions zoomed = picture;
    zoomed.title += " - " + view.name;
    zoomed.window = view.window;
    write_node_picture(dir / fmt::format("initial_{}.png", view.name), inputs.geometry, initial.nodes, zoomed);
  }
  progress(config, "wrote {}/initial.nodes, initial.png, initial.svg{}", dir.string(),
           config.output.views.empty() ? "" : fmt::format(" and {} view(s)", config.output.views.size()));
}

int run_mesh(const CaseConfig& config) {
  // Stage 1: inputs.
  const MeshInputs inputs(config);
  progress(config, "geometry: {} curves, {} segments, {} loops, area {:.6g}", inputs.geometry.curves.size(),
           inputs.geometry.segments.size(), inputs.geometry.loops.size(), inputs.geometry.area);
  // Stage 2: limits, before any large allocation.
  const double estimate = check_node_limit(config, inputs);
  // Stage 3: initial distribution.
  const InitialDistribution initial = make_initial(config, inputs);
  progress(config, "initial distribution: {} nodes (estimate {:.0f} by hexagonal packing; {} fixed, {} boundary, "
           "{} interior of which {} by overloading)",
           initial.nodes.size(), estimate, initial.nodes.count(NodeKind::Fixed),
           initial.nodes.count(NodeKind::Boundary), initial.nodes.count(NodeKind::Interior), initial.overload_nodes);
  // Stage 4: outputs. Later stages (simulation, triangulation, mesh files) follow the same pattern:
  // compute, then write atomically into the directory prepared here.
  prepare_output_directory(config);
  write_initial_outputs(config, inputs, initial);
  return kExitOk;
}

}  // namespace pdmesh
