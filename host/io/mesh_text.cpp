// Shared writer sections in pieces; see mesh_text.hpp.
#include "io/mesh_text.hpp"

#include <iterator>
#include <string_view>
#include <vector>
#include <fmt/format.h>

#include "core/errors.hpp"
#include "core/g17.hpp"
#include "core/input_file.hpp"
#include "core/text_blocks.hpp"
#include "io/mesh_io_common.hpp"

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

namespace {

// One view: time 0, time step 0, `components` values per node in point-major `values`, node tag =
// point index + 1, 17 digits.
void append_msh_view(TextSink& sink, std::string_view name, std::size_t components, std::size_t points,
                     const std::vector<double>& values) {
  std::string& out = sink.text();
  out += fmt::format("$NodeData\n1\n\"{}\"\n1\n0\n3\n0\n{}\n{}\n", name, components, points);
  append_items(sink, points, [&values, components](std::string& line, std::size_t i) {
    fmt::format_to(std::back_inserter(line), "{}", i + 1);
    for (std::size_t c = 0; c < components; ++c) {
      line += ' ';
      append_g17(line, values[i * components + c]);
    }
    line += '\n';
  });
  out += "$EndNodeData\n";
}

}  // namespace

void append_msh_spacing_node_data(TextSink& sink, const Mesh& mesh) {
  if (!mesh.spacing.empty()) append_msh_view(sink, "q", 1, mesh.spacing.size(), mesh.spacing);
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
    append_msh_view(sink, writable_name(d.name), nc, mesh.points.size(), d.values);
  }
}

}  // namespace pdmesh
