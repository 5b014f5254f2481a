// Medit .mesh writer.
// Format: Frey, "MEDIT: an interactive mesh visualization software", INRIA RT-0253, appendix (the .mesh
// keywords); mmgtools.org (mmg2d reads and writes it).
#include "io/medit_writer.hpp"

#include <iterator>
#include <vector>

#include <fmt/format.h>

#include "core/g17.hpp"
#include "core/text_blocks.hpp"
#include "io/mesh_io_common.hpp"

namespace pdmesh {
namespace {

// What the two writers share: the points, the curves and their edges, the fixed nodes.
struct MeditBoundary {
  const std::vector<Vec2>& points;
  const Mesh& curves;  // boundary_edges and curve_names
  const std::vector<NodeKind>& kind;
};

void write_head(TextSink& sink, const MeditBoundary& b, const char* region_comment) {
  std::string& out = sink.text();
  out += "MeshVersionFormatted 2\n# Written by pdmesh\nDimension 2\n";
  // An edge's reference is its curve's tag (curve_tags: c + 1, or its physical group's tag).
  const CurveTags tags = curve_tags(b.curves);
  for (const CurveTags::Group& g : tags.groups)
    out += fmt::format("# ref {}: curve {}\n", g.tag, writable_name(g.name));
  out += region_comment;
  // A vertex's reference: its first boundary edge's curve's.
  std::vector<long long> ref(b.points.size(), 0);
  for (const BoundaryEdge& e : b.curves.boundary_edges)
    for (const int v : {e.a, e.b})
      if (ref[static_cast<std::size_t>(v)] == 0)
        ref[static_cast<std::size_t>(v)] = tags.of_curve[static_cast<std::size_t>(e.curve)];
  out += fmt::format("Vertices\n{}\n", b.points.size());
  append_items(sink, b.points.size(), [&](std::string& line, std::size_t i) {
    append_g17(line, b.points[i].x);
    line += ' ';
    append_g17(line, b.points[i].y);
    fmt::format_to(std::back_inserter(line), " {}\n", ref[i]);
  });
  const std::vector<std::size_t> edges = boundary_edges_by_curve(b.curves);
  out += fmt::format("Edges\n{}\n", edges.size());
  append_items(sink, edges.size(), [&](std::string& line, std::size_t k) {
    const BoundaryEdge& e = b.curves.boundary_edges[edges[k]];
    fmt::format_to(std::back_inserter(line), "{} {} {}\n", e.a + 1, e.b + 1,
                   tags.of_curve[static_cast<std::size_t>(e.curve)]);
  });
}

void write_tail(TextSink& sink, const MeditBoundary& b) {
  std::string& out = sink.text();
  std::vector<std::size_t> corners;
  for (std::size_t i = 0; i < b.kind.size(); ++i)
    if (b.kind[i] == NodeKind::Fixed) corners.push_back(i);
  if (!corners.empty()) {
    out += fmt::format("Corners\n{}\n", corners.size());
    append_items(sink, corners.size(), [&](std::string& line, std::size_t k) {
      fmt::format_to(std::back_inserter(line), "{}\n", corners[k] + 1);
    });
  }
  out += "End\n";
}

}  // namespace

void write_medit(const Mesh& mesh, TextSink& sink) {
  check_mesh_for_writing(mesh, "Medit writer");
  const MeditBoundary b{mesh.points, mesh, mesh.kind};
  // With regional attributes a triangle's reference is its region's tag as region_surfaces gives it
  // from 1: the attribute when it is a positive integer, else j + 1 for the j-th attribute in ascending
  // order or the next free number; named in a comment. Without them 0.
  const RegionSurfaces surfaces = region_surfaces(mesh, 1);
  std::string region_comments;
  if (surfaces.regions())
    for (std::size_t j = 0; j < surfaces.names.size(); ++j)
      region_comments += fmt::format("# ref {}: region {}\n", surfaces.tags[j], surfaces.names[j]);
  write_head(sink, b, region_comments.c_str());
  sink.text() += fmt::format("Triangles\n{}\n", mesh.triangles.size());
  append_items(sink, mesh.triangles.size(), [&](std::string& line, std::size_t t) {
    const auto& v = mesh.triangles[t];
    const long long ref = surfaces.regions() ? surfaces.tags[static_cast<std::size_t>(surfaces.of_triangle[t])] : 0;
    fmt::format_to(std::back_inserter(line), "{} {} {} {}\n", v[0] + 1, v[1] + 1, v[2] + 1, ref);
  });
  write_tail(sink, b);
}

std::string medit_string(const Mesh& mesh) {
  TextSink sink;
  write_medit(mesh, sink);
  return sink.take();
}

void write_mixed_medit(const MixedMesh& mesh, TextSink& sink) {
  Mesh curves;
  curves.boundary_edges = mesh.boundary_edges;
  curves.curve_names = mesh.curve_names;
  curves.curve_groups = mesh.curve_groups;
  const std::vector<NodeKind> no_kind;
  const MeditBoundary b{mesh.points, curves, no_kind};
  // A cell's reference: without regions 0 in the core and 1 in the layer; with regions the core's
  // triangles have their region's tag (mixed_surfaces from 1, as write_medit numbers them) and the
  // layer's cells the next free one, each named in a comment.
  const MixedSurfaces surfaces = mixed_surfaces(mesh, 1);
  const bool regions = surfaces.core.regions();
  std::string region_comments;
  if (regions)
    for (std::size_t j = 0; j < surfaces.core.names.size(); ++j)
      region_comments += fmt::format("# ref {}: region {}\n", surfaces.core.tags[j], surfaces.core.names[j]);
  const long long layer_ref = regions ? surfaces.layer_tag : 1;
  region_comments += fmt::format("# ref {}: region {}\n", layer_ref, kLayerRegion);
  write_head(sink, b, region_comments.c_str());
  const auto ref = [&](std::size_t k) -> long long {
    const auto j = static_cast<std::size_t>(surfaces.of_cell[k]);
    if (j == surfaces.core.names.size()) return layer_ref;
    return regions ? surfaces.core.tags[j] : 0;
  };
  for (const int size : {3, 4}) {
    std::vector<std::size_t> cells;
    for (std::size_t k = 0; k < mesh.cells.size(); ++k)
      if ((mesh.cells[k][3] < 0 ? 3 : 4) == size) cells.push_back(k);
    sink.text() += fmt::format("{}\n{}\n", size == 3 ? "Triangles" : "Quadrilaterals", cells.size());
    append_items(sink, cells.size(), [&](std::string& line, std::size_t i) {
      const auto& c = mesh.cells[cells[i]];
      auto to = std::back_inserter(line);
      for (int k = 0; k < size; ++k) fmt::format_to(to, "{} ", c[static_cast<std::size_t>(k)] + 1);
      fmt::format_to(to, "{}\n", ref(cells[i]));
    });
  }
  write_tail(sink, b);
}

std::string mixed_medit_string(const MixedMesh& mesh) {
  TextSink sink;
  write_mixed_medit(mesh, sink);
  return sink.take();
}

}  // namespace pdmesh
