// Shared writer sections in pieces; see mesh_text.hpp.
#include "io/mesh_text.hpp"

#include <iterator>
#include <fmt/format.h>

#include "core/g17.hpp"
#include "core/text_blocks.hpp"

namespace pdmesh {

void append_point_lines(TextSink& sink, const Mesh& mesh, const char* prefix) {
  append_items(sink, mesh.points.size(), [&mesh, prefix](std::string& line, std::size_t i) {
    fmt::format_to(std::back_inserter(line), "{}{} ", prefix, i + 1);
    append_g17(line, mesh.points[i].x);
    line += ' ';
    append_g17(line, mesh.points[i].y);
    line += " 0\n";
  });
}

void append_msh_spacing_node_data(TextSink& sink, const Mesh& mesh) {
  if (mesh.spacing.empty()) return;
  // One view "q": time 0, time step 0, 1 component, a value per node (node tag = point index + 1).
  std::string& out = sink.text();
  out += fmt::format("$NodeData\n1\n\"q\"\n1\n0\n3\n0\n1\n{}\n", mesh.spacing.size());
  append_items(sink, mesh.spacing.size(), [&mesh](std::string& line, std::size_t i) {
    fmt::format_to(std::back_inserter(line), "{} ", i + 1);
    append_g17(line, mesh.spacing[i]);
    line += '\n';
  });
  out += "$EndNodeData\n";
}

}  // namespace pdmesh
