// Medit .mesh + .sol (ASCII) as metric data on a background mesh.
#include "io/medit_reader.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>

#include "core/errors.hpp"
#include "core/input_file.hpp"
#include "io/mesh_io_common.hpp"
#include "io/text_file.hpp"

namespace pdmesh {
namespace {

// The next token, skipping '#' comments to the end of their line.
std::string_view next_token(LineScanner& s, std::string_view what) {
  for (;;) {
    const std::string_view tok = s.token(what);
    if (tok.front() != '#') return tok;
    s.rest_of_line();
  }
}

// Reads the next token; nullopt-like empty view at the end of the file (End is optional).
bool next_keyword(LineScanner& s, std::string_view& keyword) {
  try {
    keyword = next_token(s, "a keyword or End");
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

// Checks MeshVersionFormatted's and Dimension's values.
void header_keyword(LineScanner& s, std::string_view keyword) {
  const std::string_view tok = next_token(s, keyword);
  const long long v = s.to_int(tok, keyword);
  if (keyword == "Dimension" && v != 2) s.fail("pdmesh reads 2-D Medit files: Dimension must be 2", tok);
  if (keyword == "MeshVersionFormatted" && (v < 1 || v > 4)) s.fail("MeshVersionFormatted must be 1 to 4", tok);
}

void check_extension(const std::filesystem::path& file, const char* want) {
  std::string ext = file.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (ext == std::string(want) + "b")
    throw InputError(
        fmt::format("{}: binary Medit files ({}b) are not read; write the ASCII {}", file.string(), want, want));
  if (ext != want)
    throw InputError(fmt::format("{}: a Medit metric needs a {} file (got '{}')", file.string(), want, ext));
}

Mesh parse_mesh(LineScanner& s) {
  Mesh mesh;
  bool has_vertices = false;
  std::string_view kw;
  while (next_keyword(s, kw) && kw != "End") {
    if (kw == "MeshVersionFormatted" || kw == "Dimension") {
      header_keyword(s, kw);
    } else if (kw == "Vertices") {
      if (has_vertices) s.fail("a second Vertices section", kw);
      has_vertices = true;
      const long long n = read_count(s, kw, 6);
      mesh.points.resize(static_cast<std::size_t>(n));
      for (auto& p : mesh.points) {
        p.x = s.to_double(next_token(s, "a vertex x"), "for a vertex x");
        p.y = s.to_double(next_token(s, "a vertex y"), "for a vertex y");
        s.to_int(next_token(s, "a vertex reference"), "vertex reference");
      }
    } else if (kw == "Triangles") {
      if (!has_vertices) s.fail("Triangles before Vertices", kw);
      const long long n = read_count(s, kw, 8);
      const auto nv = static_cast<long long>(mesh.points.size());
      for (long long k = 0; k < n; ++k) {
        std::array<int, 3> t{};
        for (int& v : t)
          v = static_cast<int>(s.to_index(next_token(s, "a triangle vertex"), 1, nv, "triangle vertex") - 1);
        s.to_int(next_token(s, "a triangle reference"), "triangle reference");
        mesh.triangles.push_back(t);
      }
    } else {
      // Sections read over, with their numbers per record.
      int per = 0;
      if (kw == "Edges")
        per = 3;
      else if (kw == "Quadrilaterals")
        per = 5;
      else if (kw == "Corners" || kw == "RequiredVertices" || kw == "Ridges" || kw == "RequiredEdges" ||
               kw == "RequiredTriangles" || kw == "RequiredQuadrilaterals")
        per = 1;
      if (per == 0)
        s.fail(
            "unknown Medit keyword (known: MeshVersionFormatted, Dimension, Vertices, Triangles, Edges, "
            "Quadrilaterals, "
            "Corners, Ridges, RequiredVertices, RequiredEdges, RequiredTriangles, RequiredQuadrilaterals, End)",
            kw);
      const std::string section(kw);
      const long long n = read_count(s, section, 2 * static_cast<std::size_t>(per));
      for (long long k = 0; k < n * per; ++k) s.to_int(next_token(s, section), fmt::format("in {}", section));
    }
  }
  if (!has_vertices) s.fail("no Vertices section");
  if (mesh.triangles.empty()) s.fail("no Triangles: a metric background mesh needs triangles");
  return mesh;
}

std::vector<Metric> parse_sol(LineScanner& s, const Mesh& mesh, const std::string& mesh_label) {
  std::string_view kw;
  while (next_keyword(s, kw) && kw != "End") {
    if (kw == "MeshVersionFormatted" || kw == "Dimension") {
      header_keyword(s, kw);
      continue;
    }
    if (kw != "SolAtVertices") s.fail("expected SolAtVertices (pdmesh reads metrics at the vertices)", kw);
    const long long n = read_count(s, kw, 6);
    if (n != static_cast<long long>(mesh.points.size()))
      s.fail(fmt::format("SolAtVertices has {} values for the {} vertices of {}", n, mesh.points.size(), mesh_label),
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
      const Vec2 p = mesh.points[i];
      check_metric(m, fmt::format("{}:{}: vertex {} ({}, {})", s.file(), s.line(), i + 1, p.x, p.y));
    }
    return metrics;
  }
  s.fail("no SolAtVertices section");
}

}  // namespace

MetricMeshData parse_medit_metric(const std::string& mesh_label, std::string mesh_text, const std::string& sol_label,
                                  std::string sol_text) {
  LineScanner ms(mesh_label, std::move(mesh_text));
  Mesh mesh = parse_mesh(ms);
  LineScanner ss(sol_label, std::move(sol_text));
  std::vector<Metric> metrics = parse_sol(ss, mesh, mesh_label);
  MeshReadReport report;
  orient_triangles_ccw(mesh, report);
  MetricMeshData d;
  d.points = std::move(mesh.points);
  d.triangles = std::move(mesh.triangles);
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
