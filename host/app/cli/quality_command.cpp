// `pdmesh quality`: mesh file in, quality table (and JSON, and a picture) out.
#include "app/cli/quality_command.hpp"

#include <filesystem>
#include <iostream>
#include <memory>

#include <fmt/format.h>

#include "app/config/case_file.hpp"
#include "app/pipeline/mesh_inputs.hpp"
#include "core/input_file.hpp"
#include "geometry/geometry_files.hpp"
#include "geometry/geometry_tree.hpp"
#include "io/mesh_formats.hpp"
#include "io/mixed_mesh.hpp"
#include "io/text_file.hpp"
#include "core/errors.hpp"
#include "mesh/mesh_topology.hpp"
#include "mesh/metric_quality.hpp"
#include "mesh/quality.hpp"
#include "io/quality_report.hpp"
#include "io/region_quality.hpp"
#include "layers/layer_measures.hpp"
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
  const std::string ext = lower_extension(path);
  CaseConfig config = ext == ".toml" ? load_case_file(path) : case_for_geometry_file(path);
  config.quiet = true;
  CaseSpacing loaded;
  loaded.inputs = std::make_unique<MeshInputs>(config);
  loaded.spacing = std::make_unique<SpacingStage>(config, *loaded.inputs, SpacingStage::Build::FieldOnly);
  return loaded;
}

// A mesh file as read: its triangles (the Mesh every measure of the table takes) and, for a file with
// quadrilaterals (.msh, .vtu, .su2, .mesh), the mixed mesh of all its cells with the cells of the
// "boundary_layer" region marked, as a layered run writes it (io/mixed_mesh.hpp). `region` says where
// the file names that region, for the text ("group", "cell data", "reference"); empty where the format cannot.
struct ReadMesh {
  Mesh mesh;
  std::optional<MixedMesh> mixed;
  bool region_found = false;
  std::string region;
};

ReadMesh read_cells(const std::string& mesh_path, MeshReadReport& report) {
  const std::string ext = lower_extension(std::filesystem::path(mesh_path));
  ReadMesh read;
  read.region = ext == ".msh" ? "group" : ext == ".vtu" ? "cell data" : ext == ".mesh" ? "reference" : "";
  SurfaceCells cells;
  cells.region = kLayerRegion;
  read.mesh = read_mesh(mesh_path, report, &cells);
  if (cells.quads.empty()) return read;
  read.mixed = mixed_mesh_of(read.mesh, cells);
  read.region_found = cells.region_found;
  return read;
}

// The mixed mesh's measures: the counts and angles of all its cells and of its boundary-layer cells
// (those of the file's "boundary_layer" region; every quad where the file names none: mixed_mesh_of),
// by the layered run's own cell measures (layers/layer_measures.hpp). The first heights and the
// growth need the case and are not measured here (docs/quality.md).
struct MixedMeasures {
  CellAngles all, layer;
};

MixedMeasures measure_mixed(const MixedMesh& m) {
  MixedMeasures out;
  for (std::size_t i = 0; i < m.cells.size(); ++i) {
    add_cell_angles(m.points, m.cells[i], out.all);
    if (m.layer[i] != 0) add_cell_angles(m.points, m.cells[i], out.layer);
  }
  return out;
}

// The text's name of the layer cells: the file's region, or every quad where the file names none
// (SU2 cannot: it has no volume markers).
std::string layer_label(const ReadMesh& read) {
  if (read.region_found) return fmt::format("boundary layer (the file's \"{}\" {})", kLayerRegion, read.region);
  if (read.region.empty()) return "quads (the format names no boundary layer)";
  return fmt::format("quads (no \"{}\" {})", kLayerRegion, read.region);
}

std::string cell_angles_json(const CellAngles& a) {
  return fmt::format(
      "{{\"cells\": {}, \"quads\": {}, \"triangles\": {}, \"max_angle\": {}, \"angles_above_150\": {}, "
      "\"inverted_cells\": {}}}",
      a.cells, a.quads, a.triangles, a.max_angle_deg, a.angles_above_150, a.inverted_cells);
}

std::string cell_angles_text(const CellAngles& a) {
  return fmt::format(
      "{} cells ({} quads, {} triangles): largest angle {:.2f} deg, {} angles above 150 deg, {} inverted", a.cells,
      a.quads, a.triangles, a.max_angle_deg, a.angles_above_150, a.inverted_cells);
}

// `title_note`: after the file name (the cells of a mesh with quads, which are drawn split).
void write_picture(const Mesh& mesh, const std::string& mesh_path, const QualityPicture& picture,
                   const std::string& title_note = "") {
  std::vector<double> values;
  MeshPictureOptions options;
  options.title = std::filesystem::path(mesh_path).filename().string() + title_note;
  if (picture.window) {
    const auto& w = *picture.window;
    Box box;
    box.add({w[0], w[1]});
    box.add({w[2], w[3]});
    options.window = box;
  }
  options.fill_regions = picture.color_by == "region";
  if (picture.color_by != "none" && !options.fill_regions) {
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
  ReadMesh read = read_cells(mesh_path, report);
  const Mesh& mesh = read.mesh;
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
  // A mesh with regions (materials): each region's triangles measured alone, for the JSON and, with two
  // or more, a row each after the table.
  add_region_quality(mesh, summary, q);
  out << format_quality_table(summary, std::filesystem::path(mesh_path).filename().string())
      << format_region_table(summary);
  // An MSH file's $Periodic pairs, as the mesh run reports them.
  for (const PeriodicLink& l : report.periodic)
    out << fmt::format("periodic: '{}' -> '{}': {} node pairs, largest mismatch {:.3g}\n",
                       mesh.curve_names[static_cast<std::size_t>(l.source_curve)],
                       mesh.curve_names[static_cast<std::size_t>(l.curve)], l.nodes.size(), l.max_mismatch);
  const std::string periodic = periodic_json(mesh.curve_names, report.periodic);
  std::string cells_member;
  if (read.mixed) {
    // The table above is the triangles'; the quads and the boundary-layer cells as the layered run's
    // quality.json counts and measures them ("boundary_layer": its tables' cells, quads, angles).
    const MixedMeasures mm = measure_mixed(*read.mixed);
    const char* layer_name = read.region_found ? "boundary_layer" : "quads";
    out << fmt::format("mixed mesh: {} points, {} cells ({} quads, {} triangles)\n  all cells: {}\n  {}: {}\n",
                       read.mixed->points.size(), mm.all.cells, mm.all.quads, mm.all.triangles,
                       cell_angles_text(mm.all), layer_label(read), cell_angles_text(mm.layer));
    cells_member =
        fmt::format(",\n  \"cells\": {{\"points\": {}, \"all\": {}, \"layer_cells\": \"{}\", \"layer\": {}}}\n",
                    read.mixed->points.size(), cell_angles_json(mm.all), layer_name, cell_angles_json(mm.layer));
  }
  if (out_json) {
    if (*out_json == "-") {
      out << quality_json(summary, mesh_path, "", periodic, cells_member);
    } else if (std::filesystem::is_directory(*out_json)) {
      err << "wrote " << write_quality_json(summary, *out_json, mesh_path, "", periodic, cells_member).string() << '\n';
    } else {
      write_text_file(*out_json, quality_json(summary, mesh_path, "", periodic, cells_member));
      err << "wrote " << *out_json << '\n';
    }
  }
  if (picture) {
    // Quads are drawn as the layered run's mesh.png draws them: split (io/mixed_mesh.hpp triangulated).
    if (read.mixed) {
      Mesh drawn = triangulated(*read.mixed);
      if (picture->color_by == "region") {
        add_file_regions(*read.mixed, mesh);
        add_layer_regions(*read.mixed, drawn);
      }
      write_picture(drawn, mesh_path, *picture,
                    fmt::format(" ({} cells, {} quads, drawn split)", read.mixed->cells.size(), read.mixed->quads()));
    } else {
      write_picture(mesh, mesh_path, *picture);
    }
    err << "wrote " << picture->path << '\n';
  }
  return 0;
}

int run_quality(const std::string& mesh_path, const std::optional<std::string>& geometry_path,
                const std::optional<std::string>& out_json, const std::optional<QualityPicture>& picture) {
  return run_quality(mesh_path, geometry_path, out_json, std::cout, std::cerr, picture);
}

}  // namespace pdmesh
