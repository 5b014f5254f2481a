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

}  // namespace

Mesh parse_su2(const std::string& file, std::string content, MeshReadReport& report) {
  LineScanner s(file, std::move(content));
  Mesh mesh;
  struct Element {
    std::array<long long, 3> v;
    int line;
    bool triangle;
    int curve;
  };
  std::vector<Element> elements;
  std::map<int, std::size_t> skipped;
  long long npoints = -1;
  bool have_dim = false;

  // Reads one element line; keeps lines (when `curve` >= 0) and triangles.
  auto read_element = [&](int curve) {
    const auto toks = s.expect_tokens("an element", '%');
    const auto type = static_cast<int>(s.to_int(toks.at(0), "element type"));
    const int n = su2_nodes(type);
    if (n == 0) s.fail("unknown SU2 element type", toks[0]);
    if (static_cast<int>(toks.size()) < 1 + n)
      s.fail(fmt::format("element of type {} needs {} point indices", type, n));
    const bool keep = curve >= 0 ? type == 3 : type == 5;
    if (!keep) {
      skipped[type]++;
      return;
    }
    Element e{{0, 0, 0}, s.line(), type == 5, curve};
    for (int k = 0; k < n; ++k)
      e.v[static_cast<std::size_t>(k)] = s.to_int(toks[static_cast<std::size_t>(1 + k)], "point index");
    elements.push_back(e);
  };

  std::string_view line;
  for (;;) {
    std::string_view raw;
    bool got = false;
    while (s.next_line(raw)) {
      const auto first = raw.find_first_not_of(" \t");
      if (first != std::string_view::npos && raw[first] != '%') {
        got = true;
        break;
      }
    }
    if (!got) break;
    line = raw;
    const std::string_view key = line.substr(0, line.find('='));
    if (key.find("NDIME") != std::string_view::npos) {
      if (s.to_int(keyed(s, line, "NDIME"), "dimension") != 2) s.fail("only 2-D SU2 meshes are supported", line);
      have_dim = true;
    } else if (key.find("NELEM") != std::string_view::npos) {
      const long long n = s.to_int(keyed(s, line, "NELEM"), "element count");
      if (n < 0) s.fail("negative element count", line);
      s.check_count(n, 6, "element count");  // "3 0 1\n"
      for (long long i = 0; i < n; ++i) read_element(-1);
    } else if (key.find("NPOIN") != std::string_view::npos) {
      const auto toks = split_tokens(keyed(s, line, "NPOIN"));
      if (toks.empty()) s.fail("expected a point count after NPOIN=", line);
      npoints = s.to_int(toks[0], "point count");
      if (npoints < 0) s.fail("negative point count", line);
      s.check_count(npoints, 4, "point count");  // "0 0\n"
      mesh.points.reserve(static_cast<std::size_t>(npoints));
      for (long long i = 0; i < npoints; ++i) {
        const auto t = s.expect_tokens("a point", '%');
        if (t.size() < 2) s.fail("a point needs x and y", fmt::format("{} fields", t.size()));
        mesh.points.push_back({s.to_double(t[0], "x"), s.to_double(t[1], "y")});
      }
    } else if (key.find("NMARK") != std::string_view::npos) {
      const long long m = s.to_int(keyed(s, line, "NMARK"), "marker count");
      s.check_count(m, 27, "marker count");  // "MARKER_TAG=\nMARKER_ELEMS=0\n"
      for (long long k = 0; k < m; ++k) {
        const auto tag = keyed(s, s.expect_line("MARKER_TAG=", '%'), "MARKER_TAG");
        const int curve = static_cast<int>(mesh.curve_names.size());
        mesh.curve_names.emplace_back(tag);
        const long long n =
            s.to_int(keyed(s, s.expect_line("MARKER_ELEMS=", '%'), "MARKER_ELEMS"), "marker element count");
        if (n < 0) s.fail("negative marker element count");
        s.check_count(n, 6, "marker element count");
        for (long long i = 0; i < n; ++i) read_element(curve);
      }
    } else {
      s.fail("unexpected line (expected NDIME=, NELEM=, NPOIN= or NMARK=)", line);
    }
  }
  if (!have_dim) throw InputError(fmt::format("{}: no NDIME= line", file));
  for (const auto& e : elements) {
    for (int k = 0; k < (e.triangle ? 3 : 2); ++k) {
      if (e.v[static_cast<std::size_t>(k)] < 0 ||
          e.v[static_cast<std::size_t>(k)] >= static_cast<long long>(mesh.points.size())) {
        throw InputError(fmt::format("{}:{}: point index {} outside 0..{}", file, e.line,
                                     e.v[static_cast<std::size_t>(k)], static_cast<long long>(mesh.points.size()) - 1));
      }
    }
    if (e.triangle) {
      mesh.triangles.push_back({static_cast<int>(e.v[0]), static_cast<int>(e.v[1]), static_cast<int>(e.v[2])});
    } else {
      mesh.boundary_edges.push_back({static_cast<int>(e.v[0]), static_cast<int>(e.v[1]), e.curve});
    }
  }
  for (const auto& [type, n] : skipped) {
    report.skipped_elements += n;
    report.notes.push_back(fmt::format("{}: skipped {} elements of SU2 type {}", file, n, type));
  }
  orient_triangles_ccw(mesh, report);
  return mesh;
}

Mesh read_su2(const std::filesystem::path& path, MeshReadReport& report) {
  return parse_su2(path.string(), read_text_file(path, InputKind::Mesh), report);
}

}  // namespace pdmesh
