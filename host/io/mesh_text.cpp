// Shared writer sections in pieces; see mesh_text.hpp.
#include "io/mesh_text.hpp"

#include <algorithm>
#include <iterator>
#include <fmt/format.h>

#include "core/errors.hpp"
#include "core/g17.hpp"
#include "core/input_file.hpp"
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

void append_msh_point_data(TextSink& sink, const Mesh& mesh) {
  for (const PointValues& d : mesh.point_data) {
    // The reader takes 1 to 9 components, as Gmsh writes views (scalar, vector, tensor).
    if (d.components < 1 || d.components > 9)
      throw InputError(fmt::format("MSH writer: point data '{}' has {} components; a $NodeData view holds 1 to 9",
                                   quote_input(d.name), d.components));
    const auto nc = static_cast<std::size_t>(d.components);
    if (d.values.size() != nc * mesh.points.size())
      throw InputError(fmt::format("MSH writer: point data '{}' holds {} values for {} points x {} components",
                                   quote_input(d.name), d.values.size(), mesh.points.size(), nc));
    std::string name = d.name;  // a quoted string tag on one line
    std::replace_if(
        name.begin(), name.end(), [](char ch) { return ch == '"' || ch == '\n' || ch == '\r'; }, '_');
    std::string& out = sink.text();
    out += fmt::format("$NodeData\n1\n\"{}\"\n1\n0\n3\n0\n{}\n{}\n", name, nc, mesh.points.size());
    append_items(sink, mesh.points.size(), [&d, nc](std::string& line, std::size_t i) {
      fmt::format_to(std::back_inserter(line), "{}", i + 1);
      for (std::size_t c = 0; c < nc; ++c) {
        line += ' ';
        append_g17(line, d.values[i * nc + c]);
      }
      line += '\n';
    });
    out += "$EndNodeData\n";
  }
}

}  // namespace pdmesh
