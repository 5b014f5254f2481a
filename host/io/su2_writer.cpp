// SU2 native mesh writer.
// Format: SU2 documentation, "Mesh File", https://su2code.github.io/docs_v7/Mesh-File/
// (section "SU2 Native Format (.su2)"): NDIME=, NELEM= (VTK type ids, 0-based point indices),
// NPOIN=, NMARK=, MARKER_TAG=, MARKER_ELEMS=.
#include "io/su2_writer.hpp"
#include "core/interrupt.hpp"

#include <iterator>

#include <fmt/format.h>

namespace pdmesh {

void write_su2(const Mesh& mesh, TextSink& sink) {
  check_mesh_for_writing(mesh, "SU2 writer");
  std::string& out = sink.text();
  out += "% Written by pdmesh\nNDIME= 2\n";
  out += fmt::format("NELEM= {}\n", mesh.triangles.size());
  // Formatted straight into `out`, numbers as coord() writes them (a temporary string per number was
  // most of the time at millions of cells).
  auto to = std::back_inserter(out);
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    if ((t & 65535) == 0) check_interrupt();
    const auto& tri = mesh.triangles[t];
    fmt::format_to(to, "5 {} {} {} {}\n", tri[0], tri[1], tri[2], t);
    sink.piece_done();
  }
  out += fmt::format("NPOIN= {}\n", mesh.points.size());
  for (std::size_t i = 0; i < mesh.points.size(); ++i) {
    if ((i & 65535) == 0) check_interrupt();
    fmt::format_to(to, "{:.17g} {:.17g} {}\n", mesh.points[i].x, mesh.points[i].y, i);
    sink.piece_done();
  }
  // One marker per curve, or per kept physical group over all its curves' edges (SU2 marker names
  // must be unique), in the order of their tags (curve_tags).
  const CurveTags tags = curve_tags(mesh);
  std::vector<std::vector<std::size_t>> per_group(tags.groups.size());
  for (std::size_t e = 0; e < mesh.boundary_edges.size(); ++e) {
    const long long tag = tags.of_curve[static_cast<std::size_t>(mesh.boundary_edges[e].curve)];
    per_group[tags.group_of_tag(tag)].push_back(e);
  }
  out += fmt::format("NMARK= {}\n", tags.groups.size());
  for (std::size_t g = 0; g < per_group.size(); ++g) {
    out += fmt::format("MARKER_TAG= {}\nMARKER_ELEMS= {}\n", writable_name(tags.groups[g].name, true),
                       per_group[g].size());
    for (auto e : per_group[g]) {
      out += fmt::format("3 {} {}\n", mesh.boundary_edges[e].a, mesh.boundary_edges[e].b);
      sink.piece_done();
    }
  }
}

std::string su2_string(const Mesh& mesh) {
  TextSink sink;
  write_su2(mesh, sink);
  return sink.take();
}

}  // namespace pdmesh
