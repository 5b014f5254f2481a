// VTK XML UnstructuredGrid reader: a small scanner over the <Piece> and <DataArray> elements (no XML
// library), with every data encoding VTK, ParaView and meshio write: ascii, binary (base64 inline)
// and appended (raw or base64), uncompressed or zlib-compressed (io/vtu_data.hpp decodes those).
// Format: https://docs.vtk.org/en/latest/design_documents/VTKFileFormats.html ("XML File Formats").
#include "io/vtu_reader.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstring>
#include <map>

#include <fmt/format.h>

#include "core/errors.hpp"
#include "core/input_file.hpp"
#include "io/text_file.hpp"
#include "io/vtu_data.hpp"

namespace pdmesh {
namespace {

// A <DataArray> as found; its values are decoded only when asked for.
struct ArrayInfo {
  std::string section;  // Points, Cells, PointData, CellData or FieldData
  std::string name;
  VtuType type;
  int components = 1;
  std::string format;              // ascii, binary or appended
  std::size_t begin = 0, end = 0;  // element content (ascii, binary)
  std::uint64_t offset = 0;        // into the appended data (appended)
  std::size_t pos = 0;             // of the tag, for line numbers
};

constexpr long long kMaxCount = 2'147'483'647;  // points and cells: a Mesh indexes them with int
constexpr long long kMaxComponents = 1000;      // VTK writes up to 9 (a tensor)

// The attributes of a start tag "<Name a="1" b='2'>" (XML entities in values decoded).
std::map<std::string, std::string> attributes(std::string_view tag) {
  std::map<std::string, std::string> out;
  std::size_t i = tag.find_first_of(" \t\r\n");
  while (i < tag.size()) {
    while (i < tag.size() && is_xml_space(tag[i])) ++i;
    const std::size_t key_begin = i;
    while (i < tag.size() && tag[i] != '=' && !is_xml_space(tag[i]) && tag[i] != '>' && tag[i] != '/') ++i;
    const std::string key(tag.substr(key_begin, i - key_begin));
    while (i < tag.size() && is_xml_space(tag[i])) ++i;
    if (key.empty() || i >= tag.size() || tag[i] != '=') {
      ++i;
      continue;
    }
    ++i;
    while (i < tag.size() && is_xml_space(tag[i])) ++i;
    if (i >= tag.size() || (tag[i] != '"' && tag[i] != '\'')) continue;
    const char quote = tag[i++];
    const std::size_t value_end = std::min(tag.find(quote, i), tag.size());
    std::string value(tag.substr(i, value_end - i));
    for (const auto& [entity, ch] : {std::pair<const char*, char>{"&lt;", '<'},
                                     {"&gt;", '>'},
                                     {"&quot;", '"'},
                                     {"&apos;", '\''},
                                     {"&amp;", '&'}}) {
      for (std::size_t p; (p = value.find(entity)) != std::string::npos;) value.replace(p, std::strlen(entity), 1, ch);
    }
    out[key] = std::move(value);
    i = value_end + 1;
  }
  return out;
}

std::string get(const std::map<std::string, std::string>& a, const std::string& key) {
  const auto it = a.find(key);
  return it == a.end() ? std::string() : it->second;
}

class VtuFile {
 public:
  VtuFile(const std::string& file, const std::string& text) : file_(file), text_(text) {}

  int line_at(std::size_t pos) const {
    return 1 + static_cast<int>(
                   std::count(text_.begin(), text_.begin() + static_cast<long>(std::min(pos, text_.size())), '\n'));
  }
  [[noreturn]] void fail(std::size_t pos, const std::string& what) const {
    throw InputError(fmt::format("{}:{}: {}", file_, line_at(pos), what));
  }
  std::string location(std::size_t pos) const { return fmt::format("{}:{}", file_, line_at(pos)); }
  std::string where(const ArrayInfo& a) const {
    return fmt::format("{}: DataArray '{}'", location(a.pos), quote_input(a.name));
  }

  void scan() {
    // Raw appended data may hold any byte, '<' included: the markup ends where it begins.
    if (const auto a = text_.find("<AppendedData"); a != std::string::npos) {
      markup_end_ = a;
      read_appended(a);
    }
    const std::size_t markup_end = markup_end_;
    std::string section;
    bool piece = false;
    bool root = false;
    std::size_t pos = 0;
    while ((pos = text_.find('<', pos)) < markup_end) {
      if (text_.compare(pos, 4, "<!--") == 0) {
        const auto close = text_.find("-->", pos);
        if (close == std::string::npos) fail(pos, "unterminated comment");
        pos = close + 3;
        continue;
      }
      const auto close = text_.find('>', pos);
      if (close == std::string::npos || close > markup_end) fail(pos, "unterminated tag (file truncated?)");
      const std::string_view tag(text_.data() + pos, close - pos + 1);
      const std::string_view element = tag.substr(1, tag.find_first_of(" >/\t\r\n", 1) - 1);
      for (const char* s : {"Points", "Cells", "PointData", "CellData", "FieldData"}) {
        if (element == s) section = s;
      }
      if (element == "VTKFile") {
        root = true;
        read_root(pos, attributes(tag));
      } else if (element == "Piece") {
        if (piece) fail(pos, "more than one <Piece> is not supported (merge the pieces, e.g. ParaView's Merge Blocks)");
        piece = true;
        const auto a = attributes(tag);
        points_ = parse_count(pos, get(a, "NumberOfPoints"), "NumberOfPoints");
        cells_ = parse_count(pos, get(a, "NumberOfCells"), "NumberOfCells");
        // A mesh indexes its points with int; the arrays' sizes are checked against these when decoded.
        for (const long long n : {points_, cells_}) {
          if (n > kMaxCount) fail(pos, fmt::format("<Piece> with {} points or cells: more than {}", n, kMaxCount));
        }
      } else if (element == "DataArray") {
        pos = read_array(pos, close, tag, section);
        continue;
      }
      pos = close + 1;
    }
    if (!root) fail(0, "no <VTKFile> element: not a VTK XML file");
    if (!piece) fail(text_.size(), "no <Piece> element: not an UnstructuredGrid file");
  }

  const std::vector<ArrayInfo>& arrays() const { return arrays_; }
  long long points() const { return points_; }
  long long cells() const { return cells_; }

  const ArrayInfo* find(std::string_view section, std::string_view name) const {
    for (const ArrayInfo& a : arrays_)
      if (a.section == section && a.name == name) return &a;
    return nullptr;
  }
  const ArrayInfo& need(std::string_view section, std::string_view name) const {
    const ArrayInfo* a = find(section, name);
    if (a == nullptr) throw InputError(fmt::format("{}: missing DataArray {}/{}", file_, section, name));
    return *a;
  }

  std::vector<double> values(const ArrayInfo& a) const {
    if (a.format == "ascii") return ascii_values(a);
    if (!compressor_error_.empty()) fail(a.pos, compressor_error_);
    if (a.format == "binary") {
      VtuBytes bytes = VtuBytes::base64(std::string_view(text_).substr(a.begin, a.end - a.begin), where(a));
      return decode_vtu_binary(bytes, encoding_, a.type);
    }
    if (appended_begin_ == std::string::npos)
      fail(a.pos, fmt::format("DataArray '{}' is appended but the file has no <AppendedData>", quote_input(a.name)));
    if (a.offset > appended_end_ - appended_begin_) {
      fail(a.pos, fmt::format("DataArray '{}' has offset {} past the end of the appended data", quote_input(a.name),
                              a.offset));
    }
    const std::size_t at = appended_begin_ + static_cast<std::size_t>(a.offset);
    const std::string_view data = std::string_view(text_).substr(at, appended_end_ - at);
    VtuBytes bytes = appended_base64_ ? VtuBytes::base64(data, where(a)) : VtuBytes::raw(data, where(a));
    return decode_vtu_binary(bytes, encoding_, a.type);
  }

 private:
  void read_root(std::size_t pos, const std::map<std::string, std::string>& a) {
    const std::string type = get(a, "type");
    if (type != "UnstructuredGrid")
      fail(pos, fmt::format("VTK file type '{}' is not UnstructuredGrid", quote_input(type)));
    const std::string order = get(a, "byte_order");
    if (!order.empty() && order != "LittleEndian" && order != "BigEndian")
      fail(pos, fmt::format("unknown byte_order '{}'", quote_input(order)));
    encoding_.big_endian = order == "BigEndian";
    const std::string header = get(a, "header_type");
    if (!header.empty() && header != "UInt32" && header != "UInt64")
      fail(pos, fmt::format("unknown header_type '{}'", quote_input(header)));
    encoding_.header_uint64 = header == "UInt64";
    const std::string compressor = get(a, "compressor");
    if (compressor == "vtkZLibDataCompressor") {
      encoding_.compressor = VtuCompressor::ZLib;
    } else if (!compressor.empty()) {
      // Reported only if a binary array is actually read: ASCII arrays are never compressed.
      compressor_error_ = fmt::format(
          "compressor '{}' is not supported (pdmesh reads uncompressed data and "
          "vtkZLibDataCompressor; in ParaView save with Compressor Type None or ZLib)",
          quote_input(compressor));
    }
  }

  void read_appended(std::size_t pos) {
    const auto close = text_.find('>', pos);
    if (close == std::string::npos) fail(pos, "unterminated <AppendedData> tag");
    const std::string encoding = get(attributes(std::string_view(text_).substr(pos, close - pos + 1)), "encoding");
    if (encoding != "raw" && encoding != "base64")
      fail(pos, fmt::format("unknown AppendedData encoding '{}'", quote_input(encoding)));
    appended_base64_ = encoding == "base64";
    const auto mark = text_.find('_', close);
    if (mark == std::string::npos) fail(pos, "<AppendedData> without the '_' that starts its data");
    appended_begin_ = mark + 1;
    const auto end = appended_base64_ ? text_.find("</AppendedData>", appended_begin_) : text_.rfind("</AppendedData>");
    appended_end_ = end == std::string::npos || end < appended_begin_ ? text_.size() : end;
  }

  std::size_t read_array(std::size_t pos, std::size_t close, std::string_view tag, const std::string& section) {
    const auto attrs = attributes(tag);
    ArrayInfo a;
    a.section = section;
    a.name = get(attrs, "Name");
    a.pos = pos;
    a.format = get(attrs, "format");
    if (a.format.empty()) a.format = "ascii";
    const std::string type = get(attrs, "type");
    if (!parse_vtu_type(type, a.type))
      fail(pos, fmt::format("DataArray '{}' has unsupported type '{}'", quote_input(a.name), quote_input(type)));
    if (const std::string nc = get(attrs, "NumberOfComponents"); !nc.empty()) {
      const long long components = parse_count(pos, nc, "NumberOfComponents");
      if (components < 1 || components > kMaxComponents) {
        fail(pos, fmt::format("DataArray '{}' has NumberOfComponents {} (1 to {})", quote_input(a.name), components,
                              kMaxComponents));
      }
      a.components = static_cast<int>(components);
    }
    const bool self_closing = tag.size() >= 2 && tag[tag.size() - 2] == '/';
    std::size_t next = close + 1;
    if (a.format == "appended") {
      a.offset = static_cast<std::uint64_t>(parse_count(pos, get(attrs, "offset"), "offset"));
      if (!self_closing) {
        const auto end = text_.find("</DataArray>", close);
        if (end != std::string::npos) next = end + 12;
      }
    } else if (a.format == "ascii" || a.format == "binary") {
      // The values are the text up to the first child element (VTK writes <InformationKey> elements
      // after them) or the end tag.
      a.begin = close + 1;
      a.end = self_closing ? a.begin : std::min(text_.find('<', a.begin), markup_end_);
      if (!self_closing) {
        const auto end = text_.find("</DataArray>", a.end);
        if (end == std::string::npos || end > markup_end_)
          fail(pos, "DataArray without </DataArray> (file truncated?)");
        next = end + 12;
      }
    } else {
      fail(pos, fmt::format("DataArray '{}' has unknown format '{}' (ascii, binary or appended)", quote_input(a.name),
                            quote_input(a.format)));
    }
    arrays_.push_back(std::move(a));
    return next;
  }

  long long parse_count(std::size_t pos, const std::string& v, const char* what) const {
    long long n = -1;
    const auto [p, ec] = std::from_chars(v.data(), v.data() + v.size(), n);
    if (ec != std::errc() || p != v.data() + v.size() || n < 0)
      fail(pos, fmt::format("bad {} '{}'", what, quote_input(v)));
    return n;
  }

  std::vector<double> ascii_values(const ArrayInfo& a) const {
    std::vector<double> out;
    std::size_t i = a.begin;
    while (i < a.end) {
      while (i < a.end && is_xml_space(text_[i])) ++i;
      if (i >= a.end) break;
      std::size_t j = i;
      while (j < a.end && !is_xml_space(text_[j])) ++j;
      double v = 0.0;
      const auto [p, ec] = std::from_chars(text_.data() + i, text_.data() + j, v);
      if (ec != std::errc() || p != text_.data() + j) {
        fail(i, fmt::format("expected a number in DataArray '{}' (got '{}')", quote_input(a.name),
                            quote_input(std::string_view(text_.data() + i, j - i))));
      }
      out.push_back(v);
      i = j;
    }
    return out;
  }

  const std::string& file_;
  const std::string& text_;
  std::vector<ArrayInfo> arrays_;
  long long points_ = 0, cells_ = 0;
  VtuEncoding encoding_;
  std::string compressor_error_;
  bool appended_base64_ = false;
  std::size_t appended_begin_ = std::string::npos, appended_end_ = std::string::npos;
  std::size_t markup_end_ = std::string::npos;  // where <AppendedData> begins (raw bytes may follow)
};

int as_index(double v, long long n, const ArrayInfo& a, const VtuFile& f) {
  if (!(v >= 0 && v < static_cast<double>(n)) || v != static_cast<double>(static_cast<long long>(v))) {
    f.fail(a.pos, fmt::format("{} holds index {} outside 0..{}", quote_input(a.name), v, n - 1));
  }
  return static_cast<int>(v);
}

// The triangles into `mesh`; with `cells` the quads into cells->quads; the cell index of each
// triangle and quad into the index lists (for the regions and the region flags).
struct CellIndex {
  std::vector<long long> triangles, quads;
};

void read_cells(const VtuFile& f, Mesh& mesh, MeshReadReport& report, const std::string& file, SurfaceCells* cells,
                CellIndex& index) {
  const ArrayInfo& conn_info = f.need("Cells", "connectivity");
  const ArrayInfo& offs_info = f.need("Cells", "offsets");
  const ArrayInfo& types_info = f.need("Cells", "types");
  const std::vector<double> conn = f.values(conn_info);
  const std::vector<double> offs = f.values(offs_info);
  const std::vector<double> types = f.values(types_info);
  const long long ncells = f.cells();
  const auto npoints = static_cast<long long>(mesh.points.size());
  if (static_cast<long long>(offs.size()) != ncells || static_cast<long long>(types.size()) != ncells) {
    f.fail(offs_info.pos, fmt::format("{} offsets and {} types for {} cells", offs.size(), types.size(), ncells));
  }
  std::map<int, std::size_t> skipped;
  std::size_t start = 0;
  mesh.triangles.reserve(static_cast<std::size_t>(ncells));
  for (long long c = 0; c < ncells; ++c) {
    const auto stop =
        static_cast<std::size_t>(as_index(offs[c], static_cast<long long>(conn.size()) + 1, offs_info, f));
    if (stop < start) f.fail(offs_info.pos, fmt::format("offsets decrease at cell {}", c));
    // VTK cell types are small integers (a UInt8 array); anything else would overflow the cast.
    if (!(types[c] >= 0 && types[c] <= 255)) f.fail(types_info.pos, fmt::format("cell {} has type {}", c, types[c]));
    const auto type = static_cast<int>(types[c]);
    if (type == 5) {
      if (stop - start != 3) f.fail(offs_info.pos, fmt::format("triangle cell {} has {} points", c, stop - start));
      std::array<int, 3> t{};
      for (int k = 0; k < 3; ++k) t[k] = as_index(conn[start + k], npoints, conn_info, f);
      mesh.triangles.push_back(t);
      index.triangles.push_back(c);
    } else if (type == 9 && cells != nullptr) {
      if (stop - start != 4) f.fail(offs_info.pos, fmt::format("quad cell {} has {} points", c, stop - start));
      std::array<int, 4> q{};
      for (int k = 0; k < 4; ++k) q[k] = as_index(conn[start + k], npoints, conn_info, f);
      cells->quads.push_back(q);
      index.quads.push_back(c);
    } else {
      skipped[type]++;
    }
    start = stop;
  }
  for (const auto& [type, n] : skipped) {
    report.skipped_elements += n;
    report.notes.push_back(fmt::format("{}: skipped {} cells of VTK type {}", file, n, type));
  }
}

// The region flags of `cells` from the cell-data array named cells->region (0 or 1 per cell).
void read_region(const VtuFile& f, SurfaceCells& cells, const CellIndex& index) {
  cells.triangle_in_region.assign(index.triangles.size(), 0);
  cells.quad_in_region.assign(index.quads.size(), 0);
  const ArrayInfo* a = f.find("CellData", cells.region);
  cells.region_found = a != nullptr;
  if (a == nullptr) return;
  const std::vector<double> v = f.values(*a);
  if (static_cast<long long>(v.size()) != f.cells())
    f.fail(a->pos,
           fmt::format("cell data '{}' holds {} values for {} cells", quote_input(a->name), v.size(), f.cells()));
  for (std::size_t c = 0; c < v.size(); ++c) {
    if (!(v[c] == 0 || v[c] == 1))
      f.fail(a->pos, fmt::format("cell data '{}' holds {} at cell {} (0 or 1)", quote_input(a->name), v[c], c));
  }
  for (std::size_t i = 0; i < index.triangles.size(); ++i)
    cells.triangle_in_region[i] = v[static_cast<std::size_t>(index.triangles[i])] != 0;
  for (std::size_t i = 0; i < index.quads.size(); ++i)
    cells.quad_in_region[i] = v[static_cast<std::size_t>(index.quads[i])] != 0;
}

// The names of a FieldData array of character codes, each name ended by a 0 (vtu_writer's curve and
// region names).
std::vector<std::string> names_of(const VtuFile& f, const ArrayInfo& a) {
  std::vector<std::string> names;
  std::string name;
  for (double v : f.values(a)) {
    if (v == 0) {
      names.push_back(name);
      name.clear();
    } else {
      if (!(v >= 1 && v <= 255)) f.fail(a.pos, fmt::format("{} holds {}, not a character code", a.name, v));
      name += static_cast<char>(static_cast<unsigned char>(v));
    }
  }
  return names;
}

// pdmesh's own arrays: the node kind (PointData), the triangles' regions (CellData "region", the
// regional attribute of each cell) and the curves (FieldData).
void read_pdmesh_arrays(const VtuFile& f, Mesh& mesh, const CellIndex& index) {
  if (const ArrayInfo* a = f.find("CellData", "region")) {
    const std::vector<double> v = f.values(*a);
    if (static_cast<long long>(v.size()) != f.cells())
      f.fail(a->pos, fmt::format("cell data 'region' holds {} values for {} cells", v.size(), f.cells()));
    mesh.region.reserve(index.triangles.size());
    for (const long long c : index.triangles) mesh.region.push_back(v[static_cast<std::size_t>(c)]);
  }
  const auto npoints = static_cast<long long>(mesh.points.size());
  if (const ArrayInfo* a = f.find("PointData", "kind")) {
    const std::vector<double> k = f.values(*a);
    if (static_cast<long long>(k.size()) != npoints)
      f.fail(a->pos, fmt::format("kind holds {} values for {} points", k.size(), npoints));
    if (std::any_of(k.begin(), k.end(), [](double v) { return v >= 0; })) {
      for (double v : k) {
        if (!(v == 0 || v == 1 || v == 2)) f.fail(a->pos, fmt::format("node kind {} is not 0, 1 or 2", v));
        mesh.kind.push_back(static_cast<NodeKind>(static_cast<int>(v)));
      }
    }
  }
  if (const ArrayInfo* a = f.find("FieldData", "curve_names")) mesh.curve_names = names_of(f, *a);
  if (const ArrayInfo* tags = f.find("FieldData", "curve_tags")) {
    // The curves' physical groups: per curve a tag (0: none) and its group's name.
    const std::vector<double> t = f.values(*tags);
    const ArrayInfo* names = f.find("FieldData", "curve_group_names");
    if (names == nullptr) f.fail(tags->pos, "curve_tags without curve_group_names");
    const std::vector<std::string> read = names_of(f, *names);
    if (t.size() != mesh.curve_names.size() || read.size() != t.size())
      f.fail(tags->pos, fmt::format("curve_tags holds {} tags and curve_group_names {} names for {} curves", t.size(),
                                    read.size(), mesh.curve_names.size()));
    std::map<long long, std::size_t> group;  // tag -> index in curve_groups
    for (std::size_t c = 0; c < t.size(); ++c) {
      if (t[c] == 0) continue;
      if (!(t[c] >= 1 && t[c] <= 9.2e18 && t[c] == std::floor(t[c])))
        f.fail(tags->pos, fmt::format("curve tag {} is not a positive integer", t[c]));
      const auto tag = static_cast<long long>(t[c]);
      const auto [at, added] = group.emplace(tag, mesh.curve_groups.size());
      if (added) mesh.curve_groups.push_back({tag, read[c], {}});
      mesh.curve_groups[at->second].curves.push_back(static_cast<int>(c));
    }
  }
  if (const ArrayInfo* names = f.find("FieldData", "region_names")) {
    const ArrayInfo* attributes = f.find("FieldData", "region_name_attributes");
    if (attributes == nullptr) f.fail(names->pos, "region_names without region_name_attributes");
    const std::vector<double> a = f.values(*attributes);
    std::vector<std::string> read = names_of(f, *names);
    if (read.size() != a.size())
      f.fail(names->pos, fmt::format("region_names holds {} names for {} attributes", read.size(), a.size()));
    for (std::size_t k = 0; k < a.size(); ++k) {
      if (!std::isfinite(a[k])) f.fail(attributes->pos, fmt::format("region attribute {} is not finite", a[k]));
      if (k > 0 && !(a[k] > a[k - 1]))
        f.fail(attributes->pos, fmt::format("region attributes are not ascending: {} after {}", a[k], a[k - 1]));
      mesh.region_names.push_back({a[k], std::move(read[k])});
    }
  }
  if (const ArrayInfo* a = f.find("FieldData", "boundary_edges")) {
    const std::vector<double> v = f.values(*a);
    if (v.size() % 3 != 0) f.fail(a->pos, "boundary_edges is not a list of triples");
    const auto curves = static_cast<long long>(mesh.curve_names.size());
    for (std::size_t e = 0; e < v.size(); e += 3) {
      mesh.boundary_edges.push_back(
          {as_index(v[e], npoints, *a, f), as_index(v[e + 1], npoints, *a, f), as_index(v[e + 2], curves, *a, f)});
    }
  }
}

// Point-data array `a` decoded, one value per component and point.
PointDataArray point_array(const VtuFile& f, const ArrayInfo& a) {
  PointDataArray out;
  out.name = a.name;
  out.components = a.components;
  out.where = f.location(a.pos);
  out.values = f.values(a);
  out.integer = !a.type.is_float;
  if (static_cast<long long>(out.values.size()) != f.points() * a.components) {
    f.fail(a.pos, fmt::format("point-data array '{}' holds {} values, expected {} components x {} points",
                              quote_input(a.name), out.values.size(), a.components, f.points()));
  }
  return out;
}

void read_point_data(const VtuFile& f, MeshPointData& data) {
  for (const ArrayInfo& a : f.arrays()) {
    if (a.section == "PointData") {
      data.point_arrays.push_back(a.name);
      // A name given twice is taken once, its first array, as `find` takes it.
      if (data.decodes(a.name) && &a == f.find("PointData", a.name)) data.arrays.push_back(point_array(f, a));
    } else if (a.section == "CellData" || a.section == "FieldData") {
      data.other_arrays.push_back(
          fmt::format("{} ({})", quote_input(a.name), a.section == "CellData" ? "cell data" : "field data"));
    }
  }
  if (const ArrayInfo* a = f.find("PointData", data.wanted)) data.array = point_array(f, *a);
}

}  // namespace

Mesh parse_vtu(const std::string& file, const std::string& content, MeshReadReport& report, MeshPointData* data,
               SurfaceCells* cells) {
  VtuFile f(file, content);
  f.scan();
  Mesh mesh;
  // The coordinates are the one DataArray inside <Points>, whatever its Name.
  const auto& arrays = f.arrays();
  const auto points_it =
      std::find_if(arrays.begin(), arrays.end(), [](const ArrayInfo& a) { return a.section == "Points"; });
  if (points_it == arrays.end()) throw InputError(fmt::format("{}: no DataArray inside <Points>", file));
  const std::vector<double> pts = f.values(*points_it);
  const long long npoints = f.points();
  if (static_cast<long long>(pts.size()) != 3 * npoints) {
    f.fail(points_it->pos, fmt::format("Points holds {} values, expected 3 x {} points", pts.size(), npoints));
  }
  mesh.points.reserve(static_cast<std::size_t>(npoints));
  for (long long i = 0; i < npoints; ++i) {
    mesh.points.push_back({pts[3 * i], pts[3 * i + 1]});
    if (pts[3 * i + 2] != 0.0 && report.off_plane.empty())
      report.off_plane = fmt::format("{}: point {} has z = {}", file, i, pts[3 * i + 2]);
  }
  if (cells != nullptr) cells->quads.clear();
  CellIndex index;
  read_cells(f, mesh, report, file, cells, index);
  read_pdmesh_arrays(f, mesh, index);
  if (data != nullptr) read_point_data(f, *data);
  orient_triangles_ccw(mesh, report);
  if (cells != nullptr) {
    read_region(f, *cells, index);
    orient_quads_ccw(mesh.points, cells->quads, file, report);
  }
  return mesh;
}

Mesh read_vtu(const std::filesystem::path& path, MeshReadReport& report, MeshPointData* data, SurfaceCells* cells) {
  return parse_vtu(path.string(), read_text_file(path, InputKind::Mesh), report, data, cells);
}

}  // namespace pdmesh
