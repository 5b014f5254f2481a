// `pdmesh quality`: mesh file in, quality table (and JSON, and a picture) out.
#include "app/cli/quality_command.hpp"

#include <filesystem>
#include <iostream>
#include <memory>

#include <fmt/format.h>

#include "app/config/case_file.hpp"
#include "app/pipeline/mesh_inputs.hpp"
#include "geometry/geometry_files.hpp"
#include "geometry/geometry_tree.hpp"
#include "io/mesh_formats.hpp"
#include "io/text_file.hpp"
#include "core/errors.hpp"
#include "mesh/mesh_topology.hpp"
#include "mesh/metric_quality.hpp"
#include "mesh/quality.hpp"
#include "io/quality_report.hpp"
#include "render/mesh_picture.hpp"
#include "spacing/spacing_field.hpp"

namespace pdmesh {
namespace {

// The final spacing field of a case (or of a geometry file alone, with the best preset): the same
// pipeline `pdmesh mesh` builds, so that meshes from elsewhere (Gmsh) are judged against the field
// pdmesh's own meshes are.
struct CaseSpacing {
  std::unique_ptr<MeshInputs> inputs;
  std::unique_ptr<SpacingStage> spacing;  // refers to *inputs
};

CaseSpacing load_spacing(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  for (auto& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  CaseConfig config = ext == ".toml" ? load_case_file(path) : case_for_geometry_file(path);
  config.quiet = true;
  CaseSpacing loaded;
  loaded.inputs = std::make_unique<MeshInputs>(config);
  loaded.spacing = std::make_unique<SpacingStage>(config, *loaded.inputs, SpacingStage::Build::FieldOnly);
  return loaded;
}

void write_picture(const Mesh& mesh, const std::string& mesh_path, const QualityPicture& picture) {
  std::vector<double> values;
  MeshPictureOptions options;
  options.title = std::filesystem::path(mesh_path).filename().string();
  if (picture.window) {
    const auto& w = *picture.window;
    Box box;
    box.add({w[0], w[1]});
    box.add({w[2], w[3]});
    options.window = box;
  }
  if (picture.color_by != "none") {
    values = metric_values(triangle_qualities(mesh), picture.color_by);
    options.triangle_values = &values;
    options.value_label = picture.color_by;
    options.value_range = picture.color_range;
  }
  write_mesh_picture(picture.path, mesh, options);
}

}  // namespace

int run_quality(const std::string& mesh_path, const std::optional<std::string>& geometry_path,
                const std::optional<std::string>& out_json, std::ostream& out, std::ostream& err,
                const std::optional<QualityPicture>& picture) {
  MeshReadReport report;
  const Mesh mesh = read_mesh(mesh_path, report);
  for (const auto& note : report.notes) err << note << '\n';
  // Measuring a folded or non-manifold mesh would report numbers of a mesh that is not there.
  if (const auto problem = find_fold_or_nonmanifold_edge(mesh)) {
    throw InputError(fmt::format("{}: {}; pdmesh quality measures only meshes without folds (docs/quality.md)",
                                 mesh_path, *problem));
  }

  CaseSpacing spacing;
  SpacingCallback q;
  if (geometry_path) {
    spacing = load_spacing(*geometry_path);
    const SpacingField* field = &spacing.spacing->asked();
    q = [field](Vec2 p) { return field->at(p); };
  }
  QualitySummary summary = summarize_quality(mesh, q);
  // A case with a metric field: the mesh measured in it too (mesh/metric_quality), C by the P1 rule
  // on the mesh.
  if (geometry_path && spacing.spacing->metric() != nullptr) {
    summary.has_metric = true;
    summary.metric = metric_quality(mesh, *spacing.spacing->metric());
  }
  out << format_quality_table(summary, std::filesystem::path(mesh_path).filename().string());
  // An MSH file's $Periodic pairs, as the mesh run reports them.
  for (const PeriodicLink& l : report.periodic)
    out << fmt::format("periodic: '{}' -> '{}': {} node pairs, largest mismatch {:.3g}\n",
                       mesh.curve_names[static_cast<std::size_t>(l.source_curve)],
                       mesh.curve_names[static_cast<std::size_t>(l.curve)], l.nodes.size(), l.max_mismatch);
  const std::string periodic = periodic_json(mesh.curve_names, report.periodic);

  if (out_json) {
    if (*out_json == "-") {
      out << quality_json(summary, mesh_path, "", periodic);
    } else if (std::filesystem::is_directory(*out_json)) {
      err << "wrote " << write_quality_json(summary, *out_json, mesh_path, "", periodic).string() << '\n';
    } else {
      write_text_file(*out_json, quality_json(summary, mesh_path, "", periodic));
      err << "wrote " << *out_json << '\n';
    }
  }
  if (picture) {
    write_picture(mesh, mesh_path, *picture);
    err << "wrote " << picture->path << '\n';
  }
  return 0;
}

int run_quality(const std::string& mesh_path, const std::optional<std::string>& geometry_path,
                const std::optional<std::string>& out_json, const std::optional<QualityPicture>& picture) {
  return run_quality(mesh_path, geometry_path, out_json, std::cout, std::cerr, picture);
}

}  // namespace pdmesh
