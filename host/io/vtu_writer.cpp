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
#include <cstring>
#include <iterator>
#include <string_view>
#include <type_traits>
#include <vector>

#include <fmt/format.h>

#include "core/g17.hpp"
#include "core/interrupt.hpp"
#include "core/parallel.hpp"
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

// The base64 text of the binary form of `count` values of type T (value(e), e = tuple * components +
// component), after their header (header_type UInt64: the byte count of the data that follows, encoded
// with it; an empty array still has its header, as VTK writes it and as readers expect). The stream
// of header and data bytes is cut into pieces of kBinaryPiece bytes, a multiple of 3, so that each
// piece encodes to whole base64 groups on its own: the pieces are encoded on several threads and
// appended in order, the text one encoder over the whole stream writes.
constexpr std::size_t kBinaryPiece = 3 << 17;
constexpr std::size_t kBinaryPiecesPerRound = 16;

template <class T, class Value>
void append_binary(TextSink& sink, std::size_t count, const Value& value) {
  const std::uint64_t bytes = static_cast<std::uint64_t>(count) * sizeof(T);
  unsigned char header[sizeof bytes];
  std::memcpy(header, &bytes, sizeof bytes);
  const std::size_t total = sizeof header + static_cast<std::size_t>(bytes);
  // Stream bytes [begin, end) into `raw`: the header's, then those of the values they fall in.
  const auto fill = [&](std::size_t begin, std::size_t end, std::vector<unsigned char>& raw) {
    raw.resize(end - begin);
    unsigned char* out = raw.data();
    for (std::size_t pos = begin; pos < std::min(end, sizeof header); ++pos) *out++ = header[pos];
    if (end <= sizeof header) return;
    const std::size_t from = std::max(begin, sizeof header) - sizeof header, to = end - sizeof header;
    for (std::size_t e = from / sizeof(T); e * sizeof(T) < to; ++e) {
      unsigned char v[sizeof(T)];
      const T x = value(e);
      std::memcpy(v, &x, sizeof(T));
      // The part of value e inside the piece: all of it but at the piece's ends.
      const std::size_t lo = std::max(from, e * sizeof(T)) - e * sizeof(T);
      const std::size_t hi = std::min(to, (e + 1) * sizeof(T)) - e * sizeof(T);
      std::memcpy(out, v + lo, hi - lo);
      out += hi - lo;
    }
  };
  const std::size_t pieces = (total + kBinaryPiece - 1) / kBinaryPiece;
  std::vector<std::string> texts(std::min(kBinaryPiecesPerRound, pieces));
  for (std::size_t first = 0; first < pieces; first += kBinaryPiecesPerRound) {
    const std::size_t round = std::min(kBinaryPiecesPerRound, pieces - first);
    parallel_for_scratch<std::vector<unsigned char>>(
        round,
        [&](std::vector<unsigned char>& raw, std::size_t k) {
          const std::size_t begin = (first + k) * kBinaryPiece, end = std::min(total, begin + kBinaryPiece);
          fill(begin, end, raw);
          texts[k].clear();
          Base64Encoder encoder(texts[k]);
          encoder.put(raw.data(), raw.size());
          encoder.finish();  // padding only after the last piece: the others are whole groups
        },
        1);
    for (std::size_t k = 0; k < round; ++k) {
      sink.text() += texts[k];
      sink.piece_done();
    }
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
    out += indent;
    out += "  ";
    append_binary<T>(sink, tuples * static_cast<std::size_t>(components), [&](std::size_t e) {
      return static_cast<T>(value(e / static_cast<std::size_t>(components), static_cast<int>(e % components)));
    });
    out += '\n';
  }
  out += indent;
  out += "</DataArray>\n";
}

}  // namespace

void write_vtu_curves(const Mesh& mesh, TextSink& sink, VtuFormat format, std::string_view indent) {
  // Boundary edges (point a, point b, curve) and the curve names as bytes, each name followed by a 0
  // byte; plain numeric arrays so that every VTK reader accepts them.
  std::string names;
  for (std::size_t c = 0; c < mesh.curve_names.size(); ++c) {
    names += curve_label(mesh, c);
    names += '\0';
  }
  const std::string field = std::string(indent) + "  ";
  std::string& out = sink.text();
  out += indent;
  out += "<FieldData>\n";
  const auto edge_tuples = " NumberOfTuples=\"" + std::to_string(mesh.boundary_edges.size()) + '"';
  data_array<std::int64_t>(sink, format, field, "boundary_edges", edge_tuples, mesh.boundary_edges.size(), 3,
                           [&](std::size_t i, int c) -> std::int64_t {
                             const auto& e = mesh.boundary_edges[i];
                             return c == 0 ? e.a : c == 1 ? e.b : e.curve;
                           });
  const auto name_tuples = " NumberOfTuples=\"" + std::to_string(names.size()) + '"';
  data_array<std::uint8_t>(sink, format, field, "curve_names", name_tuples, names.size(), 1,
                           [&](std::size_t i, int) { return static_cast<unsigned char>(names[i]); });
  if (!mesh.curve_groups.empty()) {
    // The curves' physical groups (Mesh::curve_groups): per curve its group's tag (0 for none) and
    // name (empty for none), the names as bytes like curve_names.
    const CurveTags tags = curve_tags(mesh);
    std::vector<std::int64_t> group_tag(mesh.curve_names.size(), 0);
    std::string group_names;
    for (const CurveGroupTag& g : mesh.curve_groups)
      for (const int c : g.curves)
        if (group_tag[static_cast<std::size_t>(c)] == 0 && tags.of_curve[static_cast<std::size_t>(c)] == g.tag)
          group_tag[static_cast<std::size_t>(c)] = g.tag;
    for (std::size_t c = 0; c < group_tag.size(); ++c) {
      if (group_tag[c] != 0) group_names += writable_name(tags.groups[tags.group_of_tag(group_tag[c])].name);
      group_names += '\0';
    }
    const auto curve_tuples = " NumberOfTuples=\"" + std::to_string(group_tag.size()) + '"';
    data_array<std::int64_t>(sink, format, field, "curve_tags", curve_tuples, group_tag.size(), 1,
                             [&](std::size_t i, int) { return group_tag[i]; });
    const auto group_tuples = " NumberOfTuples=\"" + std::to_string(group_names.size()) + '"';
    data_array<std::uint8_t>(sink, format, field, "curve_group_names", group_tuples, group_names.size(), 1,
                             [&](std::size_t i, int) { return static_cast<unsigned char>(group_names[i]); });
  }
  if (!mesh.region.empty() && !mesh.region_names.empty()) {
    // The regions' names the same way, with the attribute each names.
    std::string regions;
    for (const RegionName& r : mesh.region_names) {
      regions += region_label(mesh, r.attribute);
      regions += '\0';
    }
    const auto attribute_tuples = " NumberOfTuples=\"" + std::to_string(mesh.region_names.size()) + '"';
    data_array<double>(sink, format, field, "region_name_attributes", attribute_tuples, mesh.region_names.size(), 1,
                       [&](std::size_t i, int) { return mesh.region_names[i].attribute; });
    const auto region_tuples = " NumberOfTuples=\"" + std::to_string(regions.size()) + '"';
    data_array<std::uint8_t>(sink, format, field, "region_names", region_tuples, regions.size(), 1,
                             [&](std::size_t i, int) { return static_cast<unsigned char>(regions[i]); });
  }
  out += indent;
  out += "</FieldData>\n";
}

void write_vtu(const Mesh& mesh, TextSink& sink, VtuFormat format) {
  check_mesh_for_writing(mesh, "VTU writer");
  const auto quality = triangle_qualities(mesh);
  // The binary arrays are in this machine's byte order, which the file declares.
  std::string& out = sink.text();
  out += "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"";
  out += std::endian::native == std::endian::big ? "BigEndian" : "LittleEndian";
  out += "\" header_type=\"UInt64\">\n  <UnstructuredGrid>\n";
  write_vtu_curves(mesh, sink, format, "    ");

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
