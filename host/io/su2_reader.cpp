// SU2 native mesh reader.
// Format: https://su2code.github.io/docs_v7/Mesh-File/ (section "SU2 Native Format (.su2)").
#include "io/su2_reader.hpp"

#include <map>

#include <fmt/format.h>

#include "core/errors.hpp"
#include "io/text_file.hpp"

namespace pdmesh {

namespace {

// Points per element for the VTK type ids SU2 uses.
int su2_nodes(int type) {
  switch (type) {
    case 3:
      return 2;  // line
    case 5:
      return 3;  // triangle
    case 9:
      return 4;  // quadrilateral
    case 10:
      return 4;  // tetrahedron
    case 12:
      return 8;  // hexahedron
    case 13:
      return 6;  // prism
    case 14:
      return 5;  // pyramid
    default:
      return 0;
  }
}

// "KEY= value" -> value, failing when the line is another key.
std::string_view keyed(LineScanner& s, std::string_view line, std::string_view key) {
  const auto eq = line.find('=');
  std::string_view k = line.substr(0, eq == std::string_view::npos ? 0 : eq);
  while (!k.empty() && (k.back() == ' ' || k.back() == '\t')) k.remove_suffix(1);
  while (!k.empty() && (k.front() == ' ' || k.front() == '\t')) k.remove_prefix(1);
  if (eq == std::string_view::npos || k != key) s.fail(fmt::format("expected {}=", key), line);
  std::string_view v = line.substr(eq + 1);
  const auto first = v.find_first_not_of(" \t");
  v = first == std::string_view::npos ? std::string_view() : v.substr(first);
  return v.substr(0, v.find_last_not_of(" \t\r") + 1);
}

// One file's parse: a member per section (NELEM, NPOIN, NMARK), then the elements checked against
// the points and put into the mesh.
class Su2Parser {
 public:
  Su2Parser(const std::string& file, std::string content, SurfaceCells* cells)
      : file_(file), s_(file, std::move(content)), cells_(cells) {}

  Mesh parse(MeshReadReport& report) {
    std::string_view line;
    while (next_content_line(line)) {
      const std::string_view key = line.substr(0, line.find('='));
      if (key.find("NDIME") != std::string_view::npos) {
        if (s_.to_int(keyed(s_, line, "NDIME"), "dimension") != 2) s_.fail("only 2-D SU2 meshes are supported", line);
        have_dim_ = true;
      } else if (key.find("NELEM") != std::string_view::npos) {
        read_elements(line);
      } else if (key.find("NPOIN") != std::string_view::npos) {
        read_points(line);
      } else if (key.find("NMARK") != std::string_view::npos) {
        read_markers(line);
      } else {
        s_.fail("unexpected line (expected NDIME=, NELEM=, NPOIN= or NMARK=)", line);
      }
    }
    if (!have_dim_) throw InputError(fmt::format("{}: no NDIME= line", file_));
    add_elements();
    for (const auto& [type, n] : skipped_) {
      report.skipped_elements += n;
      report.notes.push_back(fmt::format("{}: skipped {} elements of SU2 type {}", file_, n, type));
    }
    orient_triangles_ccw(mesh_, report);
    if (cells_ != nullptr) {
      cells_->region_found = false;
      cells_->triangle_in_region.assign(mesh_.triangles.size(), 0);
      cells_->quad_in_region.assign(cells_->quads.size(), 0);
      orient_quads_ccw(mesh_.points, cells_->quads, file_, report);
    }
    return std::move(mesh_);
  }

 private:
  struct Element {
    std::array<long long, 4> v;
    int line;
    int nodes;  // 2 a boundary line, 3 a triangle, 4 a quadrilateral
    int curve;
  };

  // The next line that is neither blank nor a % comment; false at the end of the file.
  bool next_content_line(std::string_view& line) {
    std::string_view raw;
    while (s_.next_line(raw)) {
      const auto first = raw.find_first_not_of(" \t");
      if (first != std::string_view::npos && raw[first] != '%') {
        line = raw;
        return true;
      }
    }
    return false;
  }

  // Reads one element line; keeps lines (when `curve` >= 0), triangles and, when asked for, quads.
  void read_element(int curve) {
    const auto toks = s_.expect_tokens("an element", '%');
    const auto type = static_cast<int>(s_.to_int(toks.at(0), "element type"));
    const int n = su2_nodes(type);
    if (n == 0) s_.fail("unknown SU2 element type", toks[0]);
    if (static_cast<int>(toks.size()) < 1 + n)
      s_.fail(fmt::format("element of type {} needs {} point indices", type, n));
    const bool keep = curve >= 0 ? type == 3 : type == 5 || (type == 9 && cells_ != nullptr);
    if (!keep) {
      skipped_[type]++;
      return;
    }
    Element e{{0, 0, 0, 0}, s_.line(), n, curve};
    for (int k = 0; k < n; ++k)
      e.v[static_cast<std::size_t>(k)] = s_.to_int(toks[static_cast<std::size_t>(1 + k)], "point index");
    elements_.push_back(e);
  }

  void read_elements(std::string_view line) {
    const long long n = s_.to_int(keyed(s_, line, "NELEM"), "element count");
    if (n < 0) s_.fail("negative element count", line);
    s_.check_count(n, 6, "element count");  // "3 0 1\n"
    for (long long i = 0; i < n; ++i) read_element(-1);
  }

  void read_points(std::string_view line) {
    const auto toks = split_tokens(keyed(s_, line, "NPOIN"));
    if (toks.empty()) s_.fail("expected a point count after NPOIN=", line);
    const long long npoints = s_.to_int(toks[0], "point count");
    if (npoints < 0) s_.fail("negative point count", line);
    s_.check_count(npoints, 4, "point count");  // "0 0\n"
    mesh_.points.reserve(static_cast<std::size_t>(npoints));
    for (long long i = 0; i < npoints; ++i) {
      const auto t = s_.expect_tokens("a point", '%');
      if (t.size() < 2) s_.fail("a point needs x and y", fmt::format("{} fields", t.size()));
      mesh_.points.push_back({s_.to_double(t[0], "x"), s_.to_double(t[1], "y")});
    }
  }

  void read_markers(std::string_view line) {
    const long long m = s_.to_int(keyed(s_, line, "NMARK"), "marker count");
    s_.check_count(m, 27, "marker count");  // "MARKER_TAG=\nMARKER_ELEMS=0\n"
    for (long long k = 0; k < m; ++k) {
      const auto tag = keyed(s_, s_.expect_line("MARKER_TAG=", '%'), "MARKER_TAG");
      const int curve = static_cast<int>(mesh_.curve_names.size());
      mesh_.curve_names.emplace_back(tag);
      const long long n =
          s_.to_int(keyed(s_, s_.expect_line("MARKER_ELEMS=", '%'), "MARKER_ELEMS"), "marker element count");
      if (n < 0) s_.fail("negative marker element count");
      s_.check_count(n, 6, "marker element count");
      for (long long i = 0; i < n; ++i) read_element(curve);
    }
  }

  // The kept elements, their point indices checked, as triangles, quads and boundary edges.
  void add_elements() {
    if (cells_ != nullptr) cells_->quads.clear();
    for (const auto& e : elements_) {
      for (int k = 0; k < e.nodes; ++k) {
        if (e.v[static_cast<std::size_t>(k)] < 0 ||
            e.v[static_cast<std::size_t>(k)] >= static_cast<long long>(mesh_.points.size())) {
          throw InputError(fmt::format("{}:{}: point index {} outside 0..{}", file_, e.line,
                                       e.v[static_cast<std::size_t>(k)],
                                       static_cast<long long>(mesh_.points.size()) - 1));
        }
      }
      if (e.nodes == 4) {
        cells_->quads.push_back(
            {static_cast<int>(e.v[0]), static_cast<int>(e.v[1]), static_cast<int>(e.v[2]), static_cast<int>(e.v[3])});
      } else if (e.nodes == 3) {
        mesh_.triangles.push_back({static_cast<int>(e.v[0]), static_cast<int>(e.v[1]), static_cast<int>(e.v[2])});
      } else {
        mesh_.boundary_edges.push_back({static_cast<int>(e.v[0]), static_cast<int>(e.v[1]), e.curve});
      }
    }
  }

  const std::string& file_;
  LineScanner s_;
  Mesh mesh_;
  std::vector<Element> elements_;
  SurfaceCells* cells_;
  std::map<int, std::size_t> skipped_;
  bool have_dim_ = false;
};

}  // namespace

Mesh parse_su2(const std::string& file, std::string content, MeshReadReport& report, SurfaceCells* cells) {
  return Su2Parser(file, std::move(content), cells).parse(report);
}

Mesh read_su2(const std::filesystem::path& path, MeshReadReport& report, SurfaceCells* cells) {
  return parse_su2(path.string(), read_text_file(path, InputKind::Mesh), report, cells);
}

}  // namespace pdmesh
