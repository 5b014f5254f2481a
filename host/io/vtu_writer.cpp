// VTK XML UnstructuredGrid ASCII writer.
// Format: VTK File Formats, https://docs.vtk.org/en/latest/design_documents/VTKFileFormats.html
// (section "XML File Formats", "UnstructuredGrid" and "FieldData"); cell type 5 = VTK_TRIANGLE.
#include "io/vtu_writer.hpp"

#include <cmath>
#include <iterator>

#include <fmt/format.h>

#include "core/g17.hpp"
#include "io/mesh_io_common.hpp"
#include "mesh/quality.hpp"

namespace pdmesh {
namespace {

double finite_or_big(double v) { return std::isfinite(v) ? v : (v < 0 ? -1e300 : 1e300); }

void cell_array(std::string& out, const char* name, const std::vector<TriangleQuality>& q,
                double TriangleQuality::*field) {
  out += fmt::format("        <DataArray type=\"Float64\" Name=\"{}\" format=\"ascii\">\n", name);
  for (const auto& t : q) {
    out += "          ";
    append_g17(out, finite_or_big(t.*field));
    out += '\n';
  }
  out += "        </DataArray>\n";
}

}  // namespace

std::string vtu_string(const Mesh& mesh) {
  check_mesh_for_writing(mesh, "VTU writer");
  const auto quality = triangle_qualities(mesh);
  std::string out =
      "<?xml version=\"1.0\"?>\n"
      "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n"
      "  <UnstructuredGrid>\n";
  // FieldData: boundary edges (point a, point b, curve) and the curve names as bytes, each name
  // followed by a 0 byte; plain numeric arrays so that every VTK reader accepts them.
  std::string names;
  std::size_t name_bytes = 0;
  for (std::size_t c = 0; c < mesh.curve_names.size(); ++c) {
    for (const char ch : curve_label(mesh, c)) {
      names += fmt::format(" {}", static_cast<unsigned>(static_cast<unsigned char>(ch)));
      ++name_bytes;
    }
    names += " 0";
    ++name_bytes;
  }
  out += "    <FieldData>\n";
  out += fmt::format(
      "      <DataArray type=\"Int64\" Name=\"boundary_edges\" NumberOfComponents=\"3\" NumberOfTuples=\"{}\" "
      "format=\"ascii\">\n",
      mesh.boundary_edges.size());
  for (const auto& e : mesh.boundary_edges) out += fmt::format("        {} {} {}\n", e.a, e.b, e.curve);
  out += "      </DataArray>\n";
  out += fmt::format("      <DataArray type=\"UInt8\" Name=\"curve_names\" NumberOfTuples=\"{}\" format=\"ascii\">\n",
                     name_bytes);
  out += fmt::format("       {}\n      </DataArray>\n    </FieldData>\n", names);

  out += fmt::format("    <Piece NumberOfPoints=\"{}\" NumberOfCells=\"{}\">\n", mesh.points.size(),
                     mesh.triangles.size());
  out += "      <PointData Scalars=\"kind\">\n        <DataArray type=\"Int32\" Name=\"kind\" format=\"ascii\">\n";
  // The large arrays are formatted straight into `out` (format_to): a temporary string per number
  // took most of the writer's time at millions of cells. Numbers as coord() writes them (%.17g,
  // append_g17).
  auto to = std::back_inserter(out);
  for (std::size_t i = 0; i < mesh.points.size(); ++i)
    fmt::format_to(to, "          {}\n", mesh.kind.empty() ? -1 : static_cast<int>(mesh.kind[i]));
  out += "        </DataArray>\n";
  if (!mesh.spacing.empty()) {
    out += "        <DataArray type=\"Float64\" Name=\"q\" format=\"ascii\">\n";
    for (double q : mesh.spacing) {
      out += "          ";
      append_g17(out, q);
      out += '\n';
    }
    out += "        </DataArray>\n";
  }
  out += "      </PointData>\n";
  out += "      <CellData Scalars=\"min_angle\">\n";
  cell_array(out, "min_angle", quality, &TriangleQuality::min_angle);
  cell_array(out, "max_angle", quality, &TriangleQuality::max_angle);
  cell_array(out, "aspect_ratio", quality, &TriangleQuality::aspect_ratio);
  cell_array(out, "skewness", quality, &TriangleQuality::skewness);
  cell_array(out, "condition_number", quality, &TriangleQuality::condition_number);
  cell_array(out, "min_jacobian", quality, &TriangleQuality::min_jacobian);
  out += "      </CellData>\n";
  out += "      <Points>\n        <DataArray type=\"Float64\" Name=\"Points\" NumberOfComponents=\"3\" format=\"ascii\">\n";
  for (const auto& p : mesh.points) {
    out += "          ";
    append_g17(out, p.x);
    out += ' ';
    append_g17(out, p.y);
    out += " 0\n";
  }
  out += "        </DataArray>\n      </Points>\n";
  out += "      <Cells>\n        <DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">\n";
  for (const auto& t : mesh.triangles) fmt::format_to(to, "          {} {} {}\n", t[0], t[1], t[2]);
  out += "        </DataArray>\n        <DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n";
  for (std::size_t k = 0; k < mesh.triangles.size(); ++k) fmt::format_to(to, "          {}\n", 3 * (k + 1));
  out += "        </DataArray>\n        <DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n";
  for (std::size_t k = 0; k < mesh.triangles.size(); ++k) out += "          5\n";
  out += "        </DataArray>\n      </Cells>\n    </Piece>\n  </UnstructuredGrid>\n</VTKFile>\n";
  return out;
}

}  // namespace pdmesh
