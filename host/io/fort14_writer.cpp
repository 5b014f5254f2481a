// fort.14 writer. Format: ADCIRC's "Fort.14: Grid and Boundary Information File"
// (https://adcirc.github.io/adcirc/technical_reference/input_files/fort14.html): AGRID; NE NP;
// JN X Y DP per node; JE NHY N1 N2 N3 per element; NOPE, NETA, per open boundary NVDLL IBTYPEE and its
// nodes; NBOU, NVEL, per land boundary NVELL IBTYPE and its nodes. Indices are 1-based; text after the
// values on a line is a comment, as list-directed Fortran input reads it.
#include "io/fort14_writer.hpp"

#include <algorithm>
#include <iterator>

#include <fmt/format.h>

#include "core/interrupt.hpp"
#include "io/boundary_strings.hpp"
#include "io/mesh_io_common.hpp"
#include "io/mesh_text.hpp"

namespace pdmesh {

namespace {

bool is_open(const Mesh& mesh, const BoundaryString& s, const std::vector<std::string>& open_curves) {
  const std::string& name = mesh.curve_names[static_cast<std::size_t>(s.curve)];
  return std::find(open_curves.begin(), open_curves.end(), name) != open_curves.end();
}

std::size_t node_count(const std::vector<const BoundaryString*>& strings) {
  std::size_t n = 0;
  for (const BoundaryString* s : strings) n += s->nodes.size();
  return n;
}

}  // namespace

void write_fort14(const Mesh& mesh, const std::vector<std::string>& open_curves, TextSink& sink) {
  check_mesh_for_writing(mesh, "fort.14 writer");
  std::string& out = sink.text();
  out += "pdmesh mesh\n";
  out += fmt::format("{} {}\n", mesh.triangles.size(), mesh.points.size());
  auto to = std::back_inserter(out);
  append_point_lines(sink, mesh, "");
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    if ((t & 65535) == 0) check_interrupt();
    const auto& tri = mesh.triangles[t];
    fmt::format_to(to, "{} 3 {} {} {}\n", t + 1, tri[0] + 1, tri[1] + 1, tri[2] + 1);
    sink.piece_done();
  }
  std::vector<BoundaryString> strings = boundary_strings(mesh);
  // Outer boundary first, then islands (ADCIRC lists external boundaries before internal ones).
  std::stable_sort(strings.begin(), strings.end(),
                   [](const BoundaryString& a, const BoundaryString& b) { return !a.internal && b.internal; });
  std::vector<const BoundaryString*> open, land;
  for (const BoundaryString& s : strings) (is_open(mesh, s, open_curves) ? open : land).push_back(&s);
  const auto put_nodes = [&](const BoundaryString& s) {
    for (const int v : s.nodes) {
      fmt::format_to(to, "{}\n", v + 1);
      sink.piece_done();
    }
  };
  fmt::format_to(to, "{} = Number of open boundaries\n{} = Total number of open boundary nodes\n", open.size(),
                 node_count(open));
  for (std::size_t k = 0; k < open.size(); ++k) {
    fmt::format_to(to, "{} 0 = Number of nodes for open boundary {} ({})\n", open[k]->nodes.size(), k + 1,
                   curve_label(mesh, static_cast<std::size_t>(open[k]->curve), true));
    put_nodes(*open[k]);
  }
  fmt::format_to(to, "{} = Number of land boundaries\n{} = Total number of land boundary nodes\n", land.size(),
                 node_count(land));
  for (std::size_t k = 0; k < land.size(); ++k) {
    fmt::format_to(to, "{} {} = Number of nodes for land boundary {} ({})\n", land[k]->nodes.size(),
                   land[k]->internal ? 1 : 0, k + 1, curve_label(mesh, static_cast<std::size_t>(land[k]->curve), true));
    put_nodes(*land[k]);
  }
}

std::string fort14_string(const Mesh& mesh, const std::vector<std::string>& open_curves) {
  TextSink sink;
  write_fort14(mesh, open_curves, sink);
  return sink.take();
}

}  // namespace pdmesh
