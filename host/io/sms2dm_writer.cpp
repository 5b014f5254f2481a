// .2dm writer. Format: Aquaveo's "SMS:2D Mesh Files *.2dm" (https://www.xmswiki.com/wiki/SMS:2D_Mesh_Files_*.2dm):
// the MESH2D card, E3T id n1 n2 n3 material, ND id x y z, NS node strings of up to ten ids per line
// ending in a negated id and an optional name. Ids are 1-based.
#include "io/sms2dm_writer.hpp"

#include <iterator>

#include <fmt/format.h>

#include "core/interrupt.hpp"
#include "io/boundary_strings.hpp"
#include "io/mesh_io_common.hpp"
#include "io/mesh_text.hpp"

namespace pdmesh {

void write_sms2dm(const Mesh& mesh, TextSink& sink) {
  check_mesh_for_writing(mesh, "2dm writer");
  std::string& out = sink.text();
  out += "MESH2D\nMESHNAME \"pdmesh\"\nNUM_MATERIALS_PER_ELEM 1\n";
  auto to = std::back_inserter(out);
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    if ((t & 65535) == 0) check_interrupt();
    const auto& tri = mesh.triangles[t];
    fmt::format_to(to, "E3T {} {} {} {} 1\n", t + 1, tri[0] + 1, tri[1] + 1, tri[2] + 1);
    sink.piece_done();
  }
  append_point_lines(sink, mesh, "ND ");
  for (const BoundaryString& s : boundary_strings(mesh)) {
    for (std::size_t j = 0; j < s.nodes.size(); ++j) {
      const bool last = j + 1 == s.nodes.size();
      if (j % 10 == 0) out += "NS";
      fmt::format_to(to, " {}", last ? -(s.nodes[j] + 1) : s.nodes[j] + 1);
      if (last) out += ' ' + curve_label(mesh, static_cast<std::size_t>(s.curve), true);
      if (last || j % 10 == 9) out += '\n';
      sink.piece_done();
    }
  }
}

std::string sms2dm_string(const Mesh& mesh) {
  TextSink sink;
  write_sms2dm(mesh, sink);
  return sink.take();
}

}  // namespace pdmesh
