// Medit .mesh (ASCII) as a mesh, and with its .sol as metric data on a background mesh.
#include "io/medit_reader.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cstdint>
#include <map>
#include <optional>
#include <type_traits>
#include <unordered_map>
#include <utility>

#include "core/errors.hpp"
#include "core/input_file.hpp"
#include "io/mesh_io_common.hpp"
#include "io/mixed_mesh.hpp"
#include "io/text_file.hpp"

namespace pdmesh {
namespace {

// What the comments of a .mesh say: the names pdmesh's writer gives the references
// ("# ref N: curve NAME", "# ref N: region NAME").
struct RefNames {
  std::map<long long, std::string> curves, regions;
};

// Reads one '#' comment whose first token `tok` was just read, keeping a reference's name.
void read_comment(LineScanner& s, std::string_view tok, RefNames* names) {
  const std::string_view rest = s.rest_of_line();
  if (names == nullptr) return;
  std::string text = std::string(tok.substr(1)) + " " + std::string(rest);
  const auto first = text.find_first_not_of(' ');
  text.erase(0, first == std::string::npos ? text.size() : first);
  if (text.rfind("ref ", 0) != 0) return;
  const auto colon = text.find(':');
  if (colon == std::string::npos) return;
  long long ref = 0;
  try {
    ref = s.to_int(std::string_view(text).substr(4, colon - 4), "reference");
  } catch (const InputError&) {
    return;  // not ours: an ordinary comment
  }
  const std::string what = text.substr(colon + 1);
  for (const char* kind : {" curve ", " region "}) {
    const std::string k(kind);
    if (what.rfind(k, 0) == 0 && what.size() > k.size())
      (k == " curve " ? names->curves : names->regions)[ref] = what.substr(k.size());
  }
}

// The next token, reading '#' comments to the end of their line.
std::string_view next_token(LineScanner& s, std::string_view what, RefNames* names = nullptr) {
  for (;;) {
    const std::string_view tok = s.token(what);
    if (tok.front() != '#') return tok;
    read_comment(s, tok, names);
  }
}

// Reads the next keyword; false at the end of the file (End is optional).
bool next_keyword(LineScanner& s, std::string_view& keyword, RefNames& names) {
  try {
    keyword = next_token(s, "a keyword or End", &names);
  } catch (const InputError&) {
    return false;  // end of file
  }
  return true;
}

long long read_count(LineScanner& s, std::string_view keyword, std::size_t min_bytes_each) {
  const long long n =
      s.to_int(next_token(s, fmt::format("the count of {}", keyword)), fmt::format("count of {}", keyword));
  s.check_count(n, min_bytes_each, keyword);
  return n;
}

// Checks MeshVersionFormatted's and Dimension's values and returns the value. A mesh may have
// Dimension 3 (`planar`): Gmsh and meshio write a 2-D mesh so, its vertices at z = 0.
long long header_keyword(LineScanner& s, std::string_view keyword, bool planar = false) {
  const std::string_view tok = next_token(s, keyword);
  const long long v = s.to_int(tok, keyword);
  if (keyword == "Dimension" && v != 2 && !(planar && v == 3))
    s.fail(planar ? "pdmesh reads 2-D Medit files: Dimension must be 2, or 3 with every vertex at z = 0"
                  : "pdmesh reads 2-D Medit files: Dimension must be 2",
           tok);
  if (keyword == "MeshVersionFormatted" && (v < 1 || v > 4)) s.fail("MeshVersionFormatted must be 1 to 4", tok);
  return v;
}

void refuse_binary(const std::filesystem::path& file, const std::string& ext, const char* want) {
  if (ext == std::string(want) + "b")
    throw InputError(
        fmt::format("{}: binary Medit files ({}b) are not read; write the ASCII {}", file.string(), want, want));
}

void check_extension(const std::filesystem::path& file, const char* want) {
  const std::string ext = lower_extension(file);
  refuse_binary(file, ext, want);
  if (ext != want)
    throw InputError(fmt::format("{}: a Medit metric needs a {} file (got '{}')", file.string(), want, ext));
}

// A .mesh file's sections as written: 0-based indices, the references beside them.
struct MeditData {
  std::vector<Vec2> points;
  std::vector<std::array<int, 3>> triangles;
  std::vector<long long> triangle_refs;
  std::vector<std::array<int, 4>> quads;
  std::vector<long long> quad_refs;
  std::vector<std::array<int, 2>> edges;
  std::vector<long long> edge_refs;
  std::vector<int> corners;  // Corners and RequiredVertices, in file order
  RefNames names;
  int dimension = 2;
};

// Reads the N vertex indices of a cell or edge and its reference.
template <std::size_t N>
long long read_record(LineScanner& s, const char* what, long long nv, std::array<int, N>& v) {
  for (std::size_t k = 0; k < N; ++k)
    v[k] = static_cast<int>(
        s.to_index(next_token(s, fmt::format("a {} vertex", what)), 1, nv, fmt::format("{} vertex", what)) - 1);
  return s.to_int(next_token(s, fmt::format("a {} reference", what)), fmt::format("{} reference", what));
}

// `planar`: a Dimension 3 file is read when its vertices lie at z = 0.
MeditData parse_sections(LineScanner& s, bool planar) {
  MeditData d;
  bool has_vertices = false;
  std::string_view kw;
  const auto need_vertices = [&](std::string_view section) {
    if (!has_vertices) s.fail(fmt::format("{} before Vertices", section), section);
    return static_cast<long long>(d.points.size());
  };
  // A section of cells or edges (std::array of their vertex indices) and a reference each;
  // min_bytes: the least text one record takes.
  const auto read_cells = [&](std::string_view section, const char* what, std::size_t min_bytes, auto& cells,
                              auto& refs) {
    const long long nv = need_vertices(section);
    const long long n = read_count(s, section, min_bytes);
    for (long long k = 0; k < n; ++k) {
      typename std::remove_reference_t<decltype(cells)>::value_type c{};
      refs.push_back(read_record(s, what, nv, c));
      cells.push_back(c);
    }
  };
  while (next_keyword(s, kw, d.names) && kw != "End") {
    if (kw == "MeshVersionFormatted" || kw == "Dimension") {
      const long long v = header_keyword(s, kw, planar);
      if (kw == "Dimension") d.dimension = static_cast<int>(v);
    } else if (kw == "Vertices") {
      if (has_vertices) s.fail("a second Vertices section", kw);
      has_vertices = true;
      const long long n = read_count(s, kw, 6);
      d.points.resize(static_cast<std::size_t>(n));
      for (auto& p : d.points) {
        p.x = s.to_double(next_token(s, "a vertex x"), "for a vertex x");
        p.y = s.to_double(next_token(s, "a vertex y"), "for a vertex y");
        if (d.dimension == 3) {
          const std::string_view z = next_token(s, "a vertex z");
          if (s.to_double(z, "for a vertex z") != 0.0)
            s.fail(
                fmt::format("vertex {} is off the plane z = 0: pdmesh reads planar meshes", &p - d.points.data() + 1),
                z);
        }
        s.to_int(next_token(s, "a vertex reference"), "vertex reference");
      }
    } else if (kw == "Triangles") {
      read_cells(kw, "triangle", 8, d.triangles, d.triangle_refs);
    } else if (kw == "Quadrilaterals") {
      read_cells(kw, "quadrilateral", 10, d.quads, d.quad_refs);
    } else if (kw == "Edges") {
      read_cells(kw, "edge", 6, d.edges, d.edge_refs);
    } else if (kw == "Corners" || kw == "RequiredVertices") {
      const long long nv = need_vertices(kw);
      const std::string section(kw);
      const long long n = read_count(s, section, 2);
      for (long long k = 0; k < n; ++k)
        d.corners.push_back(
            static_cast<int>(s.to_index(next_token(s, section), 1, nv, fmt::format("{} vertex", section)) - 1));
    } else {
      // Sections read over: lists of edge, triangle or quadrilateral numbers.
      if (kw != "Ridges" && kw != "RequiredEdges" && kw != "RequiredTriangles" && kw != "RequiredQuadrilaterals")
        s.fail(
            "unknown Medit keyword (known: MeshVersionFormatted, Dimension, Vertices, Triangles, Edges, "
            "Quadrilaterals, Corners, Ridges, RequiredVertices, RequiredEdges, RequiredTriangles, "
            "RequiredQuadrilaterals, End)",
            kw);
      const std::string section(kw);
      const long long n = read_count(s, section, 2);
      for (long long k = 0; k < n; ++k) s.to_int(next_token(s, section), fmt::format("in {}", section));
    }
  }
  if (!has_vertices) s.fail("no Vertices section");
  return d;
}

std::vector<Metric> parse_sol(LineScanner& s, const std::vector<Vec2>& points, const std::string& mesh_label) {
  std::string_view kw;
  RefNames none;
  while (next_keyword(s, kw, none) && kw != "End") {
    if (kw == "MeshVersionFormatted" || kw == "Dimension") {
      header_keyword(s, kw);
      continue;
    }
    if (kw != "SolAtVertices") s.fail("expected SolAtVertices (pdmesh reads metrics at the vertices)", kw);
    const long long n = read_count(s, kw, 6);
    if (n != static_cast<long long>(points.size()))
      s.fail(fmt::format("SolAtVertices has {} values for the {} vertices of {}", n, points.size(), mesh_label),
             fmt::format("{}", n));
    const std::string_view count_tok = next_token(s, "the number of solutions");
    if (s.to_int(count_tok, "number of solutions") != 1)
      s.fail("pdmesh reads one solution per vertex, the metric (1 3)", count_tok);
    const std::string_view type_tok = next_token(s, "the solution type");
    const long long type = s.to_int(type_tok, "solution type");
    if (type != 3)
      s.fail(fmt::format(
                 "solution type {} is not a metric; pdmesh reads type 3, a symmetric tensor m11 m12 m22 per vertex{}",
                 type,
                 type == 1   ? " (type 1 is a scalar size)"
                 : type == 2 ? " (type 2 is a vector)"
                             : ""),
             type_tok);
    std::vector<Metric> metrics(static_cast<std::size_t>(n));
    for (std::size_t i = 0; i < metrics.size(); ++i) {
      Metric& m = metrics[i];
      m.m11 = s.to_double(next_token(s, "m11"), "for m11");
      m.m12 = s.to_double(next_token(s, "m12"), "for m12");
      m.m22 = s.to_double(next_token(s, "m22"), "for m22");
      const Vec2 p = points[i];
      check_metric(m, fmt::format("{}:{}: vertex {} ({}, {})", s.file(), s.line(), i + 1, p.x, p.y));
    }
    return metrics;
  }
  s.fail("no SolAtVertices section");
}

// Per triangle, its region's attribute (Mesh::region): the writer's references are j + 1 for the
// j-th region, named "region_<a>" in a comment, so the comment gives the attribute; a reference a
// comment gives another name is its own attribute, the name in `names`; a reference no comment names
// (mmg2d writes none) is taken as the attribute, which the writer then names "region_<N>". Empty
// when every reference is 0. The reference a comment names a layered run's "boundary_layer" is the
// layer's (its cells are read as SurfaceCells): a file whose other triangles all have reference 0 (a
// layered run without regions) has none; otherwise the layer's triangles are one more region,
// attribute the reference, named boundary_layer.
std::vector<double> triangle_regions(const MeditData& d, std::vector<RegionName>& names) {
  std::map<long long, double> attribute;
  std::map<double, std::string> named;
  std::optional<long long> layer;
  for (const auto& [ref, name] : d.names.regions) {
    if (name == kLayerRegion) {
      layer = ref;
      continue;
    }
    const std::optional<double> a = region_attribute(name);
    attribute[ref] = a ? *a : static_cast<double>(ref);
    if (!a) named[static_cast<double>(ref)] = name;
  }
  bool any = !attribute.empty();
  for (const long long ref : d.triangle_refs) any = any || (ref != 0 && ref != layer);
  if (!any) return {};
  if (layer) {
    attribute[*layer] = static_cast<double>(*layer);
    named[static_cast<double>(*layer)] = kLayerRegion;
  }
  for (const auto& [a, name] : named) names.push_back({a, name});
  std::vector<double> region;
  region.reserve(d.triangle_refs.size());
  for (const long long ref : d.triangle_refs) {
    const auto known = attribute.find(ref);
    region.push_back(known != attribute.end() ? known->second : static_cast<double>(ref));
  }
  return region;
}

// Per point, its kind where the file marks corners (Corners, RequiredVertices: pdmesh writes its
// fixed nodes there, mmg2d keeps them and adds the corners it finds): those Fixed, the other
// vertices of edges Boundary, the rest Interior. Empty (unknown) without either section.
std::vector<NodeKind> node_kinds(const MeditData& d, const Mesh& mesh) {
  if (d.corners.empty()) return {};
  std::vector<NodeKind> kind(mesh.points.size(), NodeKind::Interior);
  for (const BoundaryEdge& e : mesh.boundary_edges)
    for (const int v : {e.a, e.b}) kind[static_cast<std::size_t>(v)] = NodeKind::Boundary;
  for (const int v : d.corners) kind[static_cast<std::size_t>(v)] = NodeKind::Fixed;
  return kind;
}

// Drops the edges of reference 0 (no comment naming it) that lie between two cells: mmg2d writes the
// edges between a mesh's triangles and quadrilaterals (a layered run's layer top) so, as required
// edges without a reference, and they bound no domain. Said in a note.
void drop_inner_unreferenced_edges(MeditData& d, const std::string& file, MeshReadReport& report) {
  if (d.names.curves.count(0) != 0 || std::find(d.edge_refs.begin(), d.edge_refs.end(), 0) == d.edge_refs.end()) return;
  const auto key = [](int a, int b) {
    if (a > b) std::swap(a, b);
    return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 32) | static_cast<std::uint32_t>(b);
  };
  std::unordered_map<std::uint64_t, int> cells_at;
  for (const auto& t : d.triangles)
    for (std::size_t k = 0; k < 3; ++k) ++cells_at[key(t[k], t[(k + 1) % 3])];
  for (const auto& q : d.quads)
    for (std::size_t k = 0; k < 4; ++k) ++cells_at[key(q[k], q[(k + 1) % 4])];
  std::size_t kept = 0;
  for (std::size_t k = 0; k < d.edges.size(); ++k) {
    const auto it = cells_at.find(key(d.edges[k][0], d.edges[k][1]));
    if (d.edge_refs[k] == 0 && it != cells_at.end() && it->second == 2) continue;
    d.edges[kept] = d.edges[k];
    d.edge_refs[kept++] = d.edge_refs[k];
  }
  if (kept == d.edges.size()) return;
  report.notes.push_back(
      fmt::format("{}: {} edges of reference 0 between two cells are not curves", file, d.edges.size() - kept));
  d.edges.resize(kept);
  d.edge_refs.resize(kept);
}

}  // namespace

Mesh parse_medit_mesh(const std::string& file_label, std::string content, MeshReadReport& report, SurfaceCells* cells) {
  LineScanner s(file_label, std::move(content));
  MeditData d = parse_sections(s, true);
  drop_inner_unreferenced_edges(d, file_label, report);
  Mesh mesh;
  mesh.points = std::move(d.points);
  mesh.triangles = std::move(d.triangles);
  // Curves: one per edge reference (and per reference a comment names), in the order of the numbers.
  std::map<long long, int> curve_of;
  for (const auto& [ref, name] : d.names.curves) curve_of[ref] = 0;
  for (const long long ref : d.edge_refs) curve_of[ref] = 0;
  for (auto& [ref, index] : curve_of) {
    index = static_cast<int>(mesh.curve_names.size());
    const auto named = d.names.curves.find(ref);
    mesh.curve_names.push_back(named != d.names.curves.end() ? named->second : fmt::format("ref{}", ref));
  }
  for (std::size_t k = 0; k < d.edges.size(); ++k)
    mesh.boundary_edges.push_back({d.edges[k][0], d.edges[k][1], curve_of[d.edge_refs[k]]});
  mesh.region = triangle_regions(d, mesh.region_names);
  mesh.kind = node_kinds(d, mesh);
  orient_triangles_ccw(mesh, report);
  if (cells == nullptr) {
    if (!d.quads.empty()) {
      report.skipped_elements += d.quads.size();
      report.notes.push_back(fmt::format("{}: skipped {} quadrilaterals", file_label, d.quads.size()));
    }
    return mesh;
  }
  // The region: the reference a "# ref N: region NAME" comment gives cells->region.
  std::optional<long long> region_ref;
  for (const auto& [ref, name] : d.names.regions)
    if (name == cells->region) region_ref = ref;
  cells->region_found = region_ref.has_value();
  const auto in_region = [&](long long ref) -> std::uint8_t { return region_ref && ref == *region_ref ? 1 : 0; };
  cells->triangle_in_region.assign(mesh.triangles.size(), 0);
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) cells->triangle_in_region[t] = in_region(d.triangle_refs[t]);
  cells->quads = std::move(d.quads);
  cells->quad_in_region.resize(cells->quads.size());
  for (std::size_t q = 0; q < cells->quads.size(); ++q) cells->quad_in_region[q] = in_region(d.quad_refs[q]);
  orient_quads_ccw(mesh.points, cells->quads, file_label, report);
  return mesh;
}

Mesh read_medit_mesh(const std::filesystem::path& path, MeshReadReport& report, SurfaceCells* cells) {
  refuse_binary(path, lower_extension(path), ".mesh");
  return parse_medit_mesh(path.string(), read_text_file(path, InputKind::Mesh), report, cells);
}

MetricMeshData parse_medit_metric(const std::string& mesh_label, std::string mesh_text, const std::string& sol_label,
                                  std::string sol_text) {
  LineScanner ms(mesh_label, std::move(mesh_text));
  MeditData mesh = parse_sections(ms, false);
  if (mesh.triangles.empty()) ms.fail("no Triangles: a metric background mesh needs triangles");
  LineScanner ss(sol_label, std::move(sol_text));
  std::vector<Metric> metrics = parse_sol(ss, mesh.points, mesh_label);
  Mesh m;
  m.points = std::move(mesh.points);
  m.triangles = std::move(mesh.triangles);
  MeshReadReport report;
  orient_triangles_ccw(m, report);
  MetricMeshData d;
  d.points = std::move(m.points);
  d.triangles = std::move(m.triangles);
  d.metrics = std::move(metrics);
  d.what = fmt::format("{} with {}", mesh_label, sol_label);
  return d;
}

MetricMeshData load_medit_metric(const std::filesystem::path& mesh_file, const std::filesystem::path& sol_file) {
  check_extension(mesh_file, ".mesh");
  check_extension(sol_file, ".sol");
  std::string mesh_text = read_input_file(mesh_file, InputKind::Mesh);
  std::string sol_text = read_input_file(sol_file, InputKind::Mesh);
  return parse_medit_metric(mesh_file.string(), std::move(mesh_text), sol_file.string(), std::move(sol_text));
}

}  // namespace pdmesh
