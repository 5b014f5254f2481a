// Triangle .node/.ele/.poly writer.
// Format: https://www.cs.cmu.edu/~quake/triangle.node.html, https://www.cs.cmu.edu/~quake/triangle.ele.html
// and https://www.cs.cmu.edu/~quake/triangle.poly.html ("# comments" are allowed on any line).
#include "io/triangle_writer.hpp"

#include <iterator>

#include <fmt/format.h>

#include "core/interrupt.hpp"
#include "io/mesh_io_common.hpp"

namespace pdmesh {

TriangleFiles triangle_strings(const Mesh& mesh) {
  check_mesh_for_writing(mesh, "Triangle writer");
  TriangleFiles f;
  std::vector<char> on_boundary(mesh.points.size(), 0);
  for (const auto& e : mesh.boundary_edges) {
    on_boundary[static_cast<std::size_t>(e.a)] = on_boundary[static_cast<std::size_t>(e.b)] = 1;
  }
  const bool kinds = !mesh.kind.empty();
  f.node = "# Written by pdmesh (Triangle .node format)\n";
  if (kinds) f.node += "# pdmesh: attribute 1 = node kind (0 fixed, 1 boundary, 2 interior)\n";
  f.node += fmt::format("{} 2 {} 1\n", mesh.points.size(), kinds ? 1 : 0);
  // Formatted straight into the strings, numbers as coord() writes them (a temporary string per
  // number was most of the time at millions of cells).
  auto node = std::back_inserter(f.node);
  for (std::size_t i = 0; i < mesh.points.size(); ++i) {
    if ((i & 65535) == 0) check_interrupt();
    fmt::format_to(node, "{} {:.17g} {:.17g}", i + 1, mesh.points[i].x, mesh.points[i].y);
    if (kinds) fmt::format_to(node, " {}", static_cast<int>(mesh.kind[i]));
    fmt::format_to(node, " {}\n", static_cast<int>(on_boundary[i]));
  }

  // Regional attributes (Mesh::region) are the triangles' one attribute, as Triangle's -A writes them.
  const bool regions = !mesh.region.empty() && mesh.region.size() == mesh.triangles.size();
  f.ele = fmt::format("# Written by pdmesh (Triangle .ele format)\n{} 3 {}\n", mesh.triangles.size(), regions ? 1 : 0);
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    if ((t & 65535) == 0) check_interrupt();
    const auto& tri = mesh.triangles[t];
    fmt::format_to(std::back_inserter(f.ele), "{} {} {} {}", t + 1, tri[0] + 1, tri[1] + 1, tri[2] + 1);
    if (regions) fmt::format_to(std::back_inserter(f.ele), " {:.17g}", mesh.region[t]);
    f.ele += '\n';
  }

  f.poly = "# Written by pdmesh (Triangle .poly format); the points are in the .node file\n";
  // A segment's boundary marker is its curve's tag (curve_tags: c + 1, or its physical group's tag).
  const CurveTags tags = curve_tags(mesh);
  for (const CurveTags::Group& g : tags.groups)
    f.poly += fmt::format("# pdmesh curve {} {}\n", g.tag, writable_name(g.name));
  f.poly += fmt::format("0 2 0 1\n{} 1\n", mesh.boundary_edges.size());
  std::size_t k = 1;
  for (auto e : boundary_edges_by_curve(mesh)) {
    const auto& be = mesh.boundary_edges[e];
    f.poly += fmt::format("{} {} {} {}\n", k++, be.a + 1, be.b + 1, tags.of_curve[static_cast<std::size_t>(be.curve)]);
  }
  f.poly += "0\n";
  return f;
}

}  // namespace pdmesh
