// VTK XML UnstructuredGrid ASCII reader: a small scanner over <Piece> and <DataArray> elements,
// enough for the files we write and plain ASCII files from VTK/ParaView.
// Format: https://docs.vtk.org/en/latest/design_documents/VTKFileFormats.html ("XML File Formats").
#include "io/vtu_reader.hpp"

#include <algorithm>
#include <charconv>
#include <map>

#include <fmt/format.h>

#include "core/errors.hpp"
#include "io/text_file.hpp"

namespace pdmesh {
namespace {

struct Array {
  std::string section;  // Points, Cells, PointData, CellData or FieldData
  std::string name;
  std::vector<double> values;
  int line = 0;
};

class VtuScanner {
 public:
  VtuScanner(const std::string& file, const std::string& text) : file_(file), text_(text) {}

  int line_at(std::size_t pos) const {
    return 1 + static_cast<int>(std::count(text_.begin(), text_.begin() + static_cast<long>(std::min(pos, text_.size())), '\n'));
  }
  [[noreturn]] void fail(std::size_t pos, const std::string& what) const {
    throw InputError(fmt::format("{}:{}: {}", file_, line_at(pos), what));
  }
  // Value of attribute `key` in tag text, or empty.
  static std::string attr(std::string_view tag, std::string_view key) {
    const std::string pat = fmt::format(" {}=\"", key);
    const auto p = tag.find(pat);
    if (p == std::string_view::npos) return {};
    const auto start = p + pat.size();
    const auto end = tag.find('"', start);
    return end == std::string_view::npos ? std::string() : std::string(tag.substr(start, end - start));
  }

  void scan(std::map<std::string, Array>& arrays, long long& points, long long& cells) {
    std::string section;
    std::size_t pos = 0;
    bool piece = false;
    while ((pos = text_.find('<', pos)) != std::string::npos) {
      const auto close = text_.find('>', pos);
      if (close == std::string::npos) fail(pos, "unterminated tag (file truncated?)");
      const std::string_view tag(text_.data() + pos, close - pos + 1);
      // The element name of this tag decides which section later DataArrays belong to.
      const std::string_view element = tag.substr(1, tag.find_first_of(" >/\t\n", 1) - 1);
      for (const char* s : {"Points", "Cells", "PointData", "CellData", "FieldData"}) {
        if (element == s) section = s;
      }
      if (tag.substr(0, 6) == "<Piece") {
        if (piece) fail(pos, "more than one <Piece> is not supported");
        piece = true;
        points = parse_count(pos, attr(tag, "NumberOfPoints"), "NumberOfPoints");
        cells = parse_count(pos, attr(tag, "NumberOfCells"), "NumberOfCells");
      } else if (tag.substr(0, 14) == "<AppendedData") {
        fail(pos, "appended data is not supported (write the file with ASCII data arrays)");
      } else if (tag.substr(0, 10) == "<DataArray") {
        const std::string format = attr(tag, "format");
        if (format != "ascii") fail(pos, fmt::format("DataArray format '{}' is not supported (only ascii)", format));
        const auto end = text_.find("</DataArray>", close);
        if (end == std::string::npos) fail(pos, "DataArray without </DataArray> (file truncated?)");
        Array a{section, attr(tag, "Name"), {}, line_at(pos)};
        parse_values(close + 1, end, a.values);
        const std::string key = section + "/" + a.name;
        arrays[key] = std::move(a);
        pos = end;
      }
      pos = close + 1;
    }
    if (!piece) fail(text_.size(), "no <Piece> element: not an UnstructuredGrid file");
  }

 private:
  long long parse_count(std::size_t pos, const std::string& v, const char* what) const {
    long long n = -1;
    const auto [p, ec] = std::from_chars(v.data(), v.data() + v.size(), n);
    if (ec != std::errc() || p != v.data() + v.size() || n < 0) fail(pos, fmt::format("bad {} '{}'", what, v));
    return n;
  }
  void parse_values(std::size_t begin, std::size_t end, std::vector<double>& out) const {
    std::size_t i = begin;
    while (i < end) {
      while (i < end && (text_[i] == ' ' || text_[i] == '\n' || text_[i] == '\t' || text_[i] == '\r')) ++i;
      if (i >= end) break;
      std::size_t j = i;
      while (j < end && !(text_[j] == ' ' || text_[j] == '\n' || text_[j] == '\t' || text_[j] == '\r')) ++j;
      double v = 0.0;
      const auto [p, ec] = std::from_chars(text_.data() + i, text_.data() + j, v);
      if (ec != std::errc() || p != text_.data() + j) {
        fail(i, fmt::format("expected a number in a DataArray (got '{}')", std::string_view(text_.data() + i, j - i)));
      }
      out.push_back(v);
      i = j;
    }
  }

  const std::string& file_;
  const std::string& text_;
};

const Array& need(const std::map<std::string, Array>& arrays, const std::string& key, const std::string& file) {
  const auto it = arrays.find(key);
  if (it == arrays.end()) throw InputError(fmt::format("{}: missing DataArray {}", file, key));
  return it->second;
}

int as_index(double v, long long n, const Array& a, const std::string& file) {
  if (!(v >= 0 && v < static_cast<double>(n)) || v != static_cast<double>(static_cast<long long>(v))) {
    throw InputError(fmt::format("{}:{}: {} holds index {} outside 0..{}", file, a.line, a.name, v, n - 1));
  }
  return static_cast<int>(v);
}

}  // namespace

Mesh parse_vtu(const std::string& file, const std::string& content, MeshReadReport& report) {
  std::map<std::string, Array> arrays;
  long long npoints = 0, ncells = 0;
  VtuScanner(file, content).scan(arrays, npoints, ncells);
  Mesh mesh;
  // The coordinates are the one DataArray inside <Points>, whatever its Name.
  const auto points_it = std::find_if(arrays.begin(), arrays.end(), [](const auto& kv) { return kv.second.section == "Points"; });
  if (points_it == arrays.end()) throw InputError(fmt::format("{}: no DataArray inside <Points>", file));
  const Array& pts = points_it->second;
  if (static_cast<long long>(pts.values.size()) != 3 * npoints) {
    throw InputError(fmt::format("{}:{}: Points holds {} values, expected 3 x {} points", file, pts.line,
                                 pts.values.size(), npoints));
  }
  for (long long i = 0; i < npoints; ++i) mesh.points.push_back({pts.values[3 * i], pts.values[3 * i + 1]});

  const auto& conn = need(arrays, "Cells/connectivity", file);
  const auto& offs = need(arrays, "Cells/offsets", file);
  const auto& types = need(arrays, "Cells/types", file);
  if (static_cast<long long>(offs.values.size()) != ncells || static_cast<long long>(types.values.size()) != ncells) {
    throw InputError(fmt::format("{}:{}: {} offsets and {} types for {} cells", file, offs.line, offs.values.size(),
                                 types.values.size(), ncells));
  }
  std::map<int, std::size_t> skipped;
  std::size_t start = 0;
  for (long long c = 0; c < ncells; ++c) {
    const auto stop = static_cast<std::size_t>(as_index(offs.values[c], static_cast<long long>(conn.values.size()) + 1, offs, file));
    if (stop < start) throw InputError(fmt::format("{}:{}: offsets decrease at cell {}", file, offs.line, c));
    // VTK cell types are small integers (a UInt8 array); anything else would overflow the cast.
    if (!(types.values[c] >= 0 && types.values[c] <= 255)) throw InputError(fmt::format("{}:{}: cell {} has type {}", file, types.line, c, types.values[c]));
    const auto type = static_cast<int>(types.values[c]);
    if (type == 5) {
      if (stop - start != 3) throw InputError(fmt::format("{}:{}: triangle cell {} has {} points", file, offs.line, c, stop - start));
      std::array<int, 3> t{};
      for (int k = 0; k < 3; ++k) t[k] = as_index(conn.values[start + k], npoints, conn, file);
      mesh.triangles.push_back(t);
    } else {
      skipped[type]++;
    }
    start = stop;
  }
  for (const auto& [type, n] : skipped) {
    report.skipped_elements += n;
    report.notes.push_back(fmt::format("{}: skipped {} cells of VTK type {}", file, n, type));
  }

  if (const auto it = arrays.find("PointData/kind"); it != arrays.end()) {
    const auto& k = it->second.values;
    if (static_cast<long long>(k.size()) != npoints) {
      throw InputError(fmt::format("{}:{}: kind holds {} values for {} points", file, it->second.line, k.size(), npoints));
    }
    if (std::any_of(k.begin(), k.end(), [](double v) { return v >= 0; })) {
      for (double v : k) {
        if (!(v == 0 || v == 1 || v == 2)) {
          throw InputError(fmt::format("{}:{}: node kind {} is not 0, 1 or 2", file, it->second.line, v));
        }
        mesh.kind.push_back(static_cast<NodeKind>(static_cast<int>(v)));
      }
    }
  }
  if (const auto it = arrays.find("FieldData/curve_names"); it != arrays.end()) {
    std::string name;
    for (double v : it->second.values) {
      if (v == 0) {
        mesh.curve_names.push_back(name);
        name.clear();
      } else {
        if (!(v >= 1 && v <= 255)) throw InputError(fmt::format("{}:{}: curve_names holds {}, not a character code", file, it->second.line, v));
        name += static_cast<char>(static_cast<unsigned char>(v));
      }
    }
  }
  if (const auto it = arrays.find("FieldData/boundary_edges"); it != arrays.end()) {
    const auto& v = it->second.values;
    if (v.size() % 3 != 0) throw InputError(fmt::format("{}:{}: boundary_edges is not a list of triples", file, it->second.line));
    const auto curves = static_cast<long long>(mesh.curve_names.size());
    for (std::size_t e = 0; e < v.size(); e += 3) {
      mesh.boundary_edges.push_back({as_index(v[e], npoints, it->second, file), as_index(v[e + 1], npoints, it->second, file),
                                     as_index(v[e + 2], curves, it->second, file)});
    }
  }
  orient_triangles_ccw(mesh, report);
  return mesh;
}

Mesh read_vtu(const std::filesystem::path& path, MeshReadReport& report) {
  return parse_vtu(path.string(), read_text_file(path), report);
}

}  // namespace pdmesh
