// Gmsh MSH 4.1 and 2.2 ASCII writers.
// Format: Gmsh reference manual, https://gmsh.info/doc/texinfo/gmsh.html#MSH-file-format
// (section 10.1 "MSH file format", version 4.1) and
// https://gmsh.info/doc/texinfo/gmsh.html#MSH-file-format-version-2-_0028Legacy_0029
// (section 10.5 "MSH file format version 2 (Legacy)").
#include "io/msh_writer.hpp"

#include <algorithm>
#include <iterator>

#include <fmt/format.h>

#include "core/g17.hpp"
#include "core/text_blocks.hpp"
#include "io/mesh_io_common.hpp"
#include "io/mesh_text.hpp"

namespace pdmesh {
namespace {

Box box_of(const Mesh& mesh) {
  Box b;
  for (const auto& p : mesh.points) b.add(p);
  if (mesh.points.empty()) b.add({0.0, 0.0});
  return b;
}

std::string physical_names(const CurveTags& lines, const RegionSurfaces& surfaces) {
  std::string out = fmt::format("$PhysicalNames\n{}\n", lines.groups.size() + surfaces.names.size());
  for (const CurveTags::Group& g : lines.groups) out += fmt::format("1 {} \"{}\"\n", g.tag, writable_name(g.name));
  for (std::size_t j = 0; j < surfaces.names.size(); ++j)
    out += fmt::format("2 {} \"{}\"\n", surfaces.tags[j], surfaces.names[j]);
  out += "$EndPhysicalNames\n";
  return out;
}

}  // namespace

void write_msh41(const Mesh& mesh, TextSink& sink, const std::vector<PeriodicLink>* periodic) {
  check_mesh_for_writing(mesh, "MSH 4.1 writer");
  const std::size_t curves = mesh.curve_names.size();
  const std::size_t n = mesh.points.size();
  std::string& out = sink.text();
  out += "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n";
  const RegionSurfaces surfaces = region_surfaces(mesh, static_cast<long long>(curves) + 1);
  const std::size_t ns = surfaces.names.size();
  const CurveTags lines = curve_tags(mesh);
  out += physical_names(lines, surfaces);

  // Entities: no points; curve entity c + 1 carries its curve's physical tag; surface j + 1 carries
  // surfaces.tags[j]. Bounding boxes are per curve (its edges) and the mesh box for the surfaces.
  std::vector<Box> curve_box(curves);
  for (const auto& e : mesh.boundary_edges) {
    curve_box[static_cast<std::size_t>(e.curve)].add(mesh.points[static_cast<std::size_t>(e.a)]);
    curve_box[static_cast<std::size_t>(e.curve)].add(mesh.points[static_cast<std::size_t>(e.b)]);
  }
  const Box all = box_of(mesh);
  out += fmt::format("$Entities\n0 {} {} 0\n", curves, ns);
  for (std::size_t c = 0; c < curves; ++c) {
    const Box b = curve_box[c].lo.x <= curve_box[c].hi.x ? curve_box[c] : all;
    out += fmt::format("{} {} {} 0 {} {} 0 1 {} 0\n", c + 1, coord(b.lo.x), coord(b.lo.y), coord(b.hi.x), coord(b.hi.y),
                       lines.of_curve[c]);
  }
  for (std::size_t j = 0; j < ns; ++j) {
    out += fmt::format("{} {} {} 0 {} {} 0 1 {} 0\n", j + 1, coord(all.lo.x), coord(all.lo.y), coord(all.hi.x),
                       coord(all.hi.y), surfaces.tags[j]);
  }
  out += "$EndEntities\n";

  // Nodes: all in the surface entity, not parametric (gmsh looks nodes up by tag, so the
  // boundary elements may use them from another entity).
  if (n == 0) {
    out += "$Nodes\n0 0 0 0\n$EndNodes\n";
  } else {
    out += fmt::format("$Nodes\n1 {} 1 {}\n2 1 0 {}\n", n, n, n);
    // Formatted straight into the block's text (a temporary string per number was most of the time at
    // millions of nodes); numbers as coord() writes them.
    append_items(sink, n,
                 [](std::string& line, std::size_t i) { fmt::format_to(std::back_inserter(line), "{}\n", i + 1); });
    append_items(sink, n, [&mesh](std::string& line, std::size_t i) {
      append_g17(line, mesh.points[i].x);
      line += ' ';
      append_g17(line, mesh.points[i].y);
      line += " 0\n";
    });
    out += "$EndNodes\n";
  }

  // Elements: one block of 2-node lines (type 1) per curve with edges, then the triangles (type 2).
  const auto order = boundary_edges_by_curve(mesh);
  std::vector<std::size_t> per_surface(ns, 0);
  for (const int j : surfaces.of_triangle) per_surface[static_cast<std::size_t>(j)]++;
  std::size_t blocks = 0;
  for (auto k : per_surface) blocks += (k > 0);
  std::vector<std::size_t> per_curve(curves, 0);
  for (const auto& e : mesh.boundary_edges) per_curve[static_cast<std::size_t>(e.curve)]++;
  for (auto k : per_curve) blocks += (k > 0);
  const std::size_t total = mesh.boundary_edges.size() + mesh.triangles.size();
  out += fmt::format("$Elements\n{} {} {} {}\n", blocks, total, total ? 1 : 0, total);
  std::size_t tag = 1, next = 0;
  for (std::size_t c = 0; c < curves; ++c) {
    if (per_curve[c] == 0) continue;
    out += fmt::format("1 {} 1 {}\n", c + 1, per_curve[c]);
    for (std::size_t k = 0; k < per_curve[c]; ++k, ++next) {
      const auto& e = mesh.boundary_edges[order[next]];
      out += fmt::format("{} {} {}\n", tag++, e.a + 1, e.b + 1);
      sink.piece_done();
    }
  }
  // The triangles by surface, in mesh order within each (a counting sort).
  std::vector<std::size_t> start(ns + 1, 0), by_surface(mesh.triangles.size());
  for (std::size_t j = 0; j < ns; ++j) start[j + 1] = start[j] + per_surface[j];
  {
    std::vector<std::size_t> at(start.begin(), start.end() - 1);
    for (std::size_t i = 0; i < mesh.triangles.size(); ++i)
      by_surface[at[static_cast<std::size_t>(surfaces.of_triangle[i])]++] = i;
  }
  for (std::size_t j = 0; j < ns; ++j) {
    if (per_surface[j] == 0) continue;
    out += fmt::format("2 {} 2 {}\n", j + 1, per_surface[j]);
    // Triangle k of the surface's block gets the tag first_tag + k: tags run on from the elements before.
    const std::size_t first = start[j], first_tag = tag;
    append_items(sink, per_surface[j], [&](std::string& line, std::size_t k) {
      const auto& t = mesh.triangles[by_surface[first + k]];
      fmt::format_to(std::back_inserter(line), "{} {} {} {}\n", first_tag + k, t[0] + 1, t[1] + 1, t[2] + 1);
    });
    tag += per_surface[j];
  }
  out += "$EndElements\n";
  append_msh_periodic(out, periodic, true);
  append_msh_spacing_node_data(sink, mesh);
}

void write_msh22(const Mesh& mesh, TextSink& sink, const std::vector<PeriodicLink>* periodic) {
  check_mesh_for_writing(mesh, "MSH 2.2 writer");
  const std::size_t curves = mesh.curve_names.size();
  std::string& out = sink.text();
  out += "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n";
  const RegionSurfaces surfaces = region_surfaces(mesh, static_cast<long long>(curves) + 1);
  const CurveTags lines = curve_tags(mesh);
  out += physical_names(lines, surfaces);
  out += fmt::format("$Nodes\n{}\n", mesh.points.size());
  append_point_lines(sink, mesh, "");
  out += "$EndNodes\n";
  // Each element: tag, type, 2 tags (physical, elementary), nodes. Curve c is elementary entity c + 1
  // with its curve's physical tag, surface j (msh41_string) elementary entity j + 1 with physical tag
  // surfaces.tags[j].
  out += fmt::format("$Elements\n{}\n", mesh.boundary_edges.size() + mesh.triangles.size());
  std::size_t tag = 1;
  for (auto k : boundary_edges_by_curve(mesh)) {
    const auto& e = mesh.boundary_edges[k];
    out += fmt::format("{} 1 2 {} {} {} {}\n", tag++, lines.of_curve[static_cast<std::size_t>(e.curve)], e.curve + 1,
                       e.a + 1, e.b + 1);
    sink.piece_done();
  }
  const std::size_t first_tag = tag;
  append_items(sink, mesh.triangles.size(), [&](std::string& line, std::size_t i) {
    const auto& t = mesh.triangles[i];
    const int j = surfaces.of_triangle[i];
    fmt::format_to(std::back_inserter(line), "{} 2 2 {} {} {} {} {}\n", first_tag + i,
                   surfaces.tags[static_cast<std::size_t>(j)], j + 1, t[0] + 1, t[1] + 1, t[2] + 1);
  });
  out += "$EndElements\n";
  append_msh_periodic(out, periodic, false);
  append_msh_spacing_node_data(sink, mesh);
}

std::string msh41_string(const Mesh& mesh, const std::vector<PeriodicLink>* periodic) {
  TextSink sink;
  write_msh41(mesh, sink, periodic);
  return sink.take();
}

std::string msh22_string(const Mesh& mesh, const std::vector<PeriodicLink>* periodic) {
  TextSink sink;
  write_msh22(mesh, sink, periodic);
  return sink.take();
}

// Gmsh's $Periodic section: 4.1 gives the affine transform as a count and 16 values, 2.2 as a line
// "Affine" and 16 values.
void append_msh_periodic(std::string& out, const std::vector<PeriodicLink>* periodic, bool msh41) {
  if (periodic == nullptr || periodic->empty()) return;
  out += fmt::format("$Periodic\n{}\n", periodic->size());
  for (const PeriodicLink& link : *periodic) {
    out += fmt::format("1 {} {}\n", link.curve + 1, link.source_curve + 1);
    out += msh41 ? "16" : "Affine";
    for (const double v : link.affine) {
      out += ' ';
      append_g17(out, v);
    }
    out += fmt::format("\n{}\n", link.nodes.size());
    for (const auto& [image, source] : link.nodes) out += fmt::format("{} {}\n", image + 1, source + 1);
  }
  out += "$EndPeriodic\n";
}

}  // namespace pdmesh
