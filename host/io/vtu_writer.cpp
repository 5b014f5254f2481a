// VTK XML UnstructuredGrid writer, binary (base64 inline) or ASCII.
// Format: VTK File Formats, https://docs.vtk.org/en/latest/design_documents/VTKFileFormats.html
// (section "XML File Formats", "UnstructuredGrid", "FieldData" and "Binary data"); cell type 5 =
// VTK_TRIANGLE. Every array goes through one function, data_array(), so both forms hold the same
// arrays with the same names, types and values.
#include "io/vtu_writer.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <iterator>
#include <string_view>
#include <type_traits>

#include <fmt/format.h>

#include "core/interrupt.hpp"
#include "core/g17.hpp"
#include "io/mesh_io_common.hpp"
#include "io/vtu_data.hpp"
#include "mesh/quality.hpp"

namespace pdmesh {
namespace {

double finite_or_big(double v) { return std::isfinite(v) ? v : (v < 0 ? -1e300 : 1e300); }

template <class T>
constexpr const char* vtk_type_name() {
  if constexpr (std::is_same_v<T, double>) return "Float64";
  if constexpr (std::is_same_v<T, std::int64_t>) return "Int64";
  if constexpr (std::is_same_v<T, std::int32_t>) return "Int32";
  if constexpr (std::is_same_v<T, std::uint8_t>) return "UInt8";
}

template <class T>
void append_ascii(std::string& out, T v) {
  if constexpr (std::is_same_v<T, double>) {
    append_g17(out, v);
  } else {
    fmt::format_to(std::back_inserter(out), "{}", static_cast<std::int64_t>(v));
  }
}

// One <DataArray> of `tuples` tuples of `components` values of type T; value(i, c) gives component
// c of tuple i (an ASCII line holds one tuple). `indent` is the element's indentation; `extra` more
// attributes (NumberOfTuples, ...). Connectivity is a flat list in VTK (no NumberOfComponents) that
// we still write a triangle per line: `declare` false.
template <class T, class Value>
void data_array(TextSink& sink, VtuFormat format, std::string_view indent, std::string_view name,
                std::string_view extra, std::size_t tuples, int components, Value value, bool declare = true) {
  std::string& out = sink.text();
  out += indent;
  out += "<DataArray type=\"";
  out += vtk_type_name<T>();
  out += "\" Name=\"";
  out += name;
  out += '"';
  if (components != 1 && declare) {
    out += " NumberOfComponents=\"";
    append_ascii(out, static_cast<std::int64_t>(components));
    out += '"';
  }
  out += extra;
  out += format == VtuFormat::Ascii ? " format=\"ascii\">\n" : " format=\"binary\">\n";
  if (format == VtuFormat::Ascii) {
    for (std::size_t i = 0; i < tuples; ++i) {
      if ((i & 65535) == 0) check_interrupt();
      out += indent;
      out += "  ";
      for (int c = 0; c < components; ++c) {
        if (c > 0) out += ' ';
        append_ascii(out, static_cast<T>(value(i, c)));
      }
      out += '\n';
      sink.piece_done();
    }
  } else {
    // The header (header_type UInt64): the byte count of the data that follows, encoded with it
    // (an empty array still has its header, as VTK writes it and as readers expect).
    out += indent;
    out += "  ";
    Base64Encoder encoder(out);
    const std::uint64_t bytes = static_cast<std::uint64_t>(tuples) * components * sizeof(T);
    encoder.put(&bytes, sizeof bytes);
    for (std::size_t i = 0; i < tuples; ++i) {
      if ((i & 65535) == 0) check_interrupt();
      for (int c = 0; c < components; ++c) {
        const T v = static_cast<T>(value(i, c));
        encoder.put(&v, sizeof v);
      }
      sink.piece_done();
    }
    encoder.finish();
    out += '\n';
  }
  out += indent;
  out += "</DataArray>\n";
}

}  // namespace

void write_vtu(const Mesh& mesh, TextSink& sink, VtuFormat format) {
  check_mesh_for_writing(mesh, "VTU writer");
  const auto quality = triangle_qualities(mesh);
  // The binary arrays are in this machine's byte order, which the file declares.
  std::string& out = sink.text();
  out += "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"";
  out += std::endian::native == std::endian::big ? "BigEndian" : "LittleEndian";
  out += "\" header_type=\"UInt64\">\n  <UnstructuredGrid>\n";
  // FieldData: boundary edges (point a, point b, curve) and the curve names as bytes, each name
  // followed by a 0 byte; plain numeric arrays so that every VTK reader accepts them.
  std::string names;
  for (std::size_t c = 0; c < mesh.curve_names.size(); ++c) {
    names += curve_label(mesh, c);
    names += '\0';
  }
  const std::string_view field = "      ";
  out += "    <FieldData>\n";
  const auto edge_tuples = " NumberOfTuples=\"" + std::to_string(mesh.boundary_edges.size()) + '"';
  data_array<std::int64_t>(sink, format, field, "boundary_edges", edge_tuples, mesh.boundary_edges.size(), 3,
                           [&](std::size_t i, int c) -> std::int64_t {
                             const auto& e = mesh.boundary_edges[i];
                             return c == 0 ? e.a : c == 1 ? e.b : e.curve;
                           });
  const auto name_tuples = " NumberOfTuples=\"" + std::to_string(names.size()) + '"';
  data_array<std::uint8_t>(sink, format, field, "curve_names", name_tuples, names.size(), 1,
                           [&](std::size_t i, int) { return static_cast<unsigned char>(names[i]); });
  out += "    </FieldData>\n";

  out += "    <Piece NumberOfPoints=\"" + std::to_string(mesh.points.size()) + "\" NumberOfCells=\"" +
         std::to_string(mesh.triangles.size()) + "\">\n";
  const std::string_view array = "        ";
  out += "      <PointData Scalars=\"kind\">\n";
  data_array<std::int32_t>(sink, format, array, "kind", "", mesh.points.size(), 1,
                           [&](std::size_t i, int) { return mesh.kind.empty() ? -1 : static_cast<int>(mesh.kind[i]); });
  if (!mesh.spacing.empty())
    data_array<double>(sink, format, array, "q", "", mesh.spacing.size(), 1,
                       [&](std::size_t i, int) { return mesh.spacing[i]; });
  for (const PointValues& d : mesh.point_data) {
    const auto at = [&d](std::size_t i, int c) { return d.values[i * static_cast<std::size_t>(d.components) + c]; };
    std::string name = d.name;  // an attribute value: no markup characters
    std::replace_if(
        name.begin(), name.end(), [](char ch) { return ch == '"' || ch == '<' || ch == '>' || ch == '&'; }, '_');
    if (d.integer)
      data_array<std::int64_t>(sink, format, array, name, "", mesh.points.size(), d.components,
                               [&](std::size_t i, int c) { return static_cast<std::int64_t>(at(i, c)); });
    else
      data_array<double>(sink, format, array, name, "", mesh.points.size(), d.components,
                         [&](std::size_t i, int c) { return finite_or_big(at(i, c)); });
  }
  out += "      </PointData>\n";
  out += "      <CellData Scalars=\"min_angle\">\n";
  const auto metric = [&](const char* name, double TriangleQuality::*m) {
    data_array<double>(sink, format, array, name, "", quality.size(), 1,
                       [&](std::size_t i, int) { return finite_or_big(quality[i].*m); });
  };
  metric("min_angle", &TriangleQuality::min_angle);
  metric("max_angle", &TriangleQuality::max_angle);
  metric("aspect_ratio", &TriangleQuality::aspect_ratio);
  metric("skewness", &TriangleQuality::skewness);
  metric("condition_number", &TriangleQuality::condition_number);
  metric("min_jacobian", &TriangleQuality::min_jacobian);
  if (mesh.region.size() == mesh.triangles.size() && !mesh.region.empty())
    data_array<double>(sink, format, array, "region", "", mesh.region.size(), 1,
                       [&](std::size_t i, int) { return mesh.region[i]; });
  out += "      </CellData>\n";
  out += "      <Points>\n";
  data_array<double>(sink, format, array, "Points", "", mesh.points.size(), 3, [&](std::size_t i, int c) {
    return c == 0 ? mesh.points[i].x : c == 1 ? mesh.points[i].y : 0.0;
  });
  out += "      </Points>\n      <Cells>\n";
  data_array<std::int64_t>(
      sink, format, array, "connectivity", "", mesh.triangles.size(), 3,
      [&](std::size_t k, int c) { return mesh.triangles[k][c]; }, false);
  data_array<std::int64_t>(sink, format, array, "offsets", "", mesh.triangles.size(), 1,
                           [](std::size_t k, int) { return static_cast<std::int64_t>(3 * (k + 1)); });
  data_array<std::uint8_t>(sink, format, array, "types", "", mesh.triangles.size(), 1,
                           [](std::size_t, int) { return 5; });
  out += "      </Cells>\n    </Piece>\n  </UnstructuredGrid>\n</VTKFile>\n";
}

std::string vtu_string(const Mesh& mesh, VtuFormat format) {
  TextSink sink;
  write_vtu(mesh, sink, format);
  return sink.take();
}

}  // namespace pdmesh
