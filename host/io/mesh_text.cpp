// Shared writer sections in pieces; see mesh_text.hpp.
#include "io/mesh_text.hpp"

#include <iterator>
#include <fmt/format.h>

#include "core/g17.hpp"
#include "core/interrupt.hpp"

namespace pdmesh {

void append_point_lines(TextSink& sink, const Mesh& mesh, const char* prefix) {
  std::string& out = sink.text();
  auto to = std::back_inserter(out);
  for (std::size_t i = 0; i < mesh.points.size(); ++i) {
    if ((i & 65535) == 0) check_interrupt();
    fmt::format_to(to, "{}{} ", prefix, i + 1);
    append_g17(out, mesh.points[i].x);
    out += ' ';
    append_g17(out, mesh.points[i].y);
    out += " 0\n";
    sink.piece_done();
  }
}

void append_msh_spacing_node_data(TextSink& sink, const Mesh& mesh) {
  if (mesh.spacing.empty()) return;
  // One view "q": time 0, time step 0, 1 component, a value per node (node tag = point index + 1).
  std::string& out = sink.text();
  out += fmt::format("$NodeData\n1\n\"q\"\n1\n0\n3\n0\n1\n{}\n", mesh.spacing.size());
  auto to = std::back_inserter(out);
  for (std::size_t i = 0; i < mesh.spacing.size(); ++i) {
    fmt::format_to(to, "{} ", i + 1);
    append_g17(out, mesh.spacing[i]);
    out += '\n';
    sink.piece_done();
  }
  out += "$EndNodeData\n";
}

}  // namespace pdmesh
