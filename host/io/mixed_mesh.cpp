// Writers of MixedMesh (io/mixed_mesh.hpp): the formats of msh_writer, vtu_writer and su2_writer with
// quadrilaterals beside the triangles and the boundary layer as a region of its own.
#include "io/mixed_mesh.hpp"

#include <algorithm>
#include <cstdint>
#include <iterator>
#include <string>
#include <fmt/format.h>
#include <fmt/ranges.h>

#include "core/atomic_file.hpp"
#include "core/errors.hpp"
#include "core/g17.hpp"
#include "core/text_blocks.hpp"
#include "core/text_sink.hpp"
#include "io/cgns_writer.hpp"
#include "io/medit_writer.hpp"
#include "io/mesh_formats.hpp"
#include "io/mesh_io_common.hpp"
#include "io/msh_writer.hpp"
#include "io/openfoam_writer.hpp"
#include "io/vtu_writer.hpp"

namespace pdmesh {

namespace {

// The curves and boundary edges as a Mesh, for the labels and the per-curve order the writers share.
Mesh curves_of(const MixedMesh& m) {
  Mesh out;
  out.boundary_edges = m.boundary_edges;
  out.curve_names = m.curve_names;
  out.curve_groups = m.curve_groups;
  return out;
}

void append_point(std::string& out, Vec2 p) {
  append_g17(out, p.x);
  out += ' ';
  append_g17(out, p.y);
}

int size_of(const std::array<int, 4>& c) { return c[3] < 0 ? 3 : 4; }

// <PointData> with the mesh's extra arrays (a motion run's node_id), ASCII like the rest of the file.
void append_point_data(std::string& out, const MixedMesh& mesh) {
  out += "<PointData>\n";
  for (const PointValues& d : mesh.point_data) {
    std::string name = d.name;  // an attribute value: no markup characters
    for (char& ch : name)
      if (ch == '"' || ch == '<' || ch == '>' || ch == '&') ch = '_';
    out += fmt::format("<DataArray type=\"{}\" Name=\"{}\" NumberOfComponents=\"{}\" format=\"ascii\">\n",
                       d.integer ? "Int64" : "Float64", name, d.components);
    const auto per_point = static_cast<std::size_t>(d.components);
    for (std::size_t i = 0; i < d.values.size(); ++i) {
      if (d.integer)
        out += std::to_string(static_cast<std::int64_t>(d.values[i]));
      else
        append_g17(out, d.values[i]);
      out += (i + 1) % per_point == 0 ? '\n' : ' ';
    }
    out += "</DataArray>\n";
  }
  out += "</PointData>\n";
}

}  // namespace

std::size_t MixedMesh::quads() const {
  std::size_t n = 0;
  for (const auto& c : cells) n += c[3] >= 0;
  return n;
}

namespace {

// The writers append to a TextSink as the triangle meshes' do (io/msh_writer.cpp): the long sections
// (points, cells) are formatted in blocks on the worker threads and appended in order
// (core/text_blocks.hpp), the same text a loop over the items appends; a sink bound to the file writes
// it in pieces.
void write_mixed_msh41(const MixedMesh& mesh, TextSink& sink, const std::vector<PeriodicLink>* periodic) {
  const Mesh curves = curves_of(mesh);
  const std::size_t nc = mesh.curve_names.size();
  const CurveTags lines = curve_tags(curves);
  const MixedSurfaces surfaces = mixed_surfaces(mesh, static_cast<long long>(nc) + 1);
  const std::size_t ns = surfaces.core.names.size();  // the layer is surface entity ns + 1
  std::string& out = sink.text();
  out += "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n";
  out += fmt::format("$PhysicalNames\n{}\n", lines.groups.size() + ns + 1);
  for (const CurveTags::Group& g : lines.groups) out += fmt::format("1 {} \"{}\"\n", g.tag, writable_name(g.name));
  for (std::size_t j = 0; j < ns; ++j)
    out += fmt::format("2 {} \"{}\"\n", surfaces.core.tags[j], surfaces.core.names[j]);
  out += fmt::format("2 {} \"{}\"\n$EndPhysicalNames\n", surfaces.layer_tag, kLayerRegion);
  Box all;
  for (const Vec2 p : mesh.points) all.add(p);
  if (mesh.points.empty()) all.add({0.0, 0.0});
  const auto box = [&](const Box& b) {
    return fmt::format("{} {} 0 {} {} 0", coord(b.lo.x), coord(b.lo.y), coord(b.hi.x), coord(b.hi.y));
  };
  out += fmt::format("$Entities\n0 {} {} 0\n", nc, ns + 1);
  for (std::size_t c = 0; c < nc; ++c) out += fmt::format("{} {} 1 {} 0\n", c + 1, box(all), lines.of_curve[c]);
  for (std::size_t j = 0; j < ns; ++j) out += fmt::format("{} {} 1 {} 0\n", j + 1, box(all), surfaces.core.tags[j]);
  out += fmt::format("{} {} 1 {} 0\n$EndEntities\n", ns + 1, box(all), surfaces.layer_tag);
  const std::size_t n = mesh.points.size();
  out += fmt::format("$Nodes\n1 {} 1 {}\n2 1 0 {}\n", n, n, n);
  append_items(sink, n,
               [](std::string& line, std::size_t i) { fmt::format_to(std::back_inserter(line), "{}\n", i + 1); });
  append_items(sink, n, [&mesh](std::string& line, std::size_t i) {
    append_point(line, mesh.points[i]);
    line += " 0\n";
  });
  out += "$EndNodes\n";
  // Blocks: the lines of each curve, then (surface, type) = (j + 1, 2) per core surface j and
  // (ns + 1, 2), (ns + 1, 3) for the layer, where not empty.
  std::vector<std::size_t> per_curve(nc, 0);
  for (const auto& e : mesh.boundary_edges) per_curve[static_cast<std::size_t>(e.curve)]++;
  struct Block {
    int entity, type;
    std::vector<std::size_t> cells;
  };
  std::vector<Block> blocks;
  for (std::size_t j = 0; j < ns; ++j) blocks.push_back({static_cast<int>(j + 1), 2, {}});
  blocks.push_back({static_cast<int>(ns + 1), 2, {}});
  blocks.push_back({static_cast<int>(ns + 1), 3, {}});
  for (std::size_t k = 0; k < mesh.cells.size(); ++k) {
    const bool quad = size_of(mesh.cells[k]) == 4;
    const auto j = static_cast<std::size_t>(surfaces.of_cell[k]);
    blocks[j < ns ? j : (quad ? ns + 1 : ns)].cells.push_back(k);
  }
  std::size_t block_count = 0;
  for (auto k : per_curve) block_count += k > 0;
  for (const Block& b : blocks) block_count += !b.cells.empty();
  const std::size_t total = mesh.boundary_edges.size() + mesh.cells.size();
  out += fmt::format("$Elements\n{} {} 1 {}\n", block_count, total, total);
  std::size_t tag = 1, next = 0;
  const auto order = boundary_edges_by_curve(curves);
  for (std::size_t c = 0; c < nc; ++c) {
    if (per_curve[c] == 0) continue;
    out += fmt::format("1 {} 1 {}\n", c + 1, per_curve[c]);
    for (std::size_t k = 0; k < per_curve[c]; ++k, ++next) {
      const auto& e = mesh.boundary_edges[order[next]];
      fmt::format_to(std::back_inserter(out), "{} {} {}\n", tag++, e.a + 1, e.b + 1);
      sink.piece_done();
    }
  }
  for (const Block& b : blocks) {
    if (b.cells.empty()) continue;
    out += fmt::format("2 {} {} {}\n", b.entity, b.type, b.cells.size());
    // Cell k of the block gets the tag first_tag + k: tags run on from the elements before.
    const std::size_t first_tag = tag;
    append_items(sink, b.cells.size(), [&](std::string& line, std::size_t k) {
      const auto& c = mesh.cells[b.cells[k]];
      fmt::format_to(std::back_inserter(line), "{}", first_tag + k);
      for (int i = 0; i < size_of(c); ++i)
        fmt::format_to(std::back_inserter(line), " {}", c[static_cast<std::size_t>(i)] + 1);
      line += '\n';
    });
    tag += b.cells.size();
  }
  out += "$EndElements\n";
  append_msh_periodic(out, periodic, true);
}

void write_mixed_vtu(const MixedMesh& mesh, TextSink& sink) {
  std::string& out = sink.text();
  out +=
      "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\">\n"
      "<UnstructuredGrid>\n";
  // The region names go with the field data where there are regions (write_vtu_curves writes them for
  // a mesh with regional attributes).
  Mesh curves = curves_of(mesh);
  if (!mesh.region.empty()) {
    curves.region = mesh.region;
    curves.region_names = mesh.region_names;
  }
  write_vtu_curves(curves, sink, VtuFormat::Ascii, "");
  out += fmt::format(
      "<Piece NumberOfPoints=\"{}\" NumberOfCells=\"{}\">\n<Points>\n"
      "<DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n",
      mesh.points.size(), mesh.cells.size());
  append_items(sink, mesh.points.size(), [&mesh](std::string& line, std::size_t i) {
    append_point(line, mesh.points[i]);
    line += " 0\n";
  });
  out += "</DataArray>\n</Points>\n";
  if (!mesh.point_data.empty()) append_point_data(out, mesh);
  out += "<Cells>\n<DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">\n";
  append_items(sink, mesh.cells.size(), [&mesh](std::string& line, std::size_t k) {
    const auto& c = mesh.cells[k];
    for (int i = 0; i < size_of(c); ++i)
      fmt::format_to(std::back_inserter(line), "{}{}", i ? " " : "", c[static_cast<std::size_t>(i)]);
    line += '\n';
  });
  out += "</DataArray>\n<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n";
  std::vector<std::size_t> offsets(mesh.cells.size());
  std::size_t offset = 0;
  for (std::size_t k = 0; k < mesh.cells.size(); ++k)
    offsets[k] = offset += static_cast<std::size_t>(size_of(mesh.cells[k]));
  append_items(sink, offsets.size(), [&offsets](std::string& line, std::size_t k) {
    fmt::format_to(std::back_inserter(line), "{}\n", offsets[k]);
  });
  out += "</DataArray>\n<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n";
  append_items(sink, mesh.cells.size(),
               [&mesh](std::string& line, std::size_t k) { line += size_of(mesh.cells[k]) == 4 ? "9\n" : "5\n"; });
  out += fmt::format(
      "</DataArray>\n</Cells>\n<CellData Scalars=\"{0}\">\n"
      "<DataArray type=\"UInt8\" Name=\"{0}\" format=\"ascii\">\n",
      kLayerRegion);
  append_items(sink, mesh.layer.size(),
               [&mesh](std::string& line, std::size_t k) { line += mesh.layer[k] ? "1\n" : "0\n"; });
  out += "</DataArray>\n";
  if (mesh.region.size() == mesh.cells.size() && !mesh.region.empty()) {
    // Every cell's regional attribute, as a triangle mesh's .vtu has it: the layer's cells that of the
    // region they lie in (the "boundary_layer" array above tells them apart).
    out += "<DataArray type=\"Float64\" Name=\"region\" format=\"ascii\">\n";
    append_items(sink, mesh.region.size(), [&mesh](std::string& line, std::size_t k) {
      append_g17(line, mesh.region[k]);
      line += '\n';
    });
    out += "</DataArray>\n";
  }
  out += "</CellData>\n</Piece>\n</UnstructuredGrid>\n</VTKFile>\n";
}

void write_mixed_su2(const MixedMesh& mesh, TextSink& sink) {
  const Mesh curves = curves_of(mesh);
  std::string& out = sink.text();
  out += fmt::format("NDIME= 2\nNELEM= {}\n", mesh.cells.size());
  // The core's cells, then the layer's, each in mesh order; element k of that order has the id k.
  std::vector<std::size_t> order;
  order.reserve(mesh.cells.size());
  for (int region = 0; region < 2; ++region)
    for (std::size_t k = 0; k < mesh.cells.size(); ++k)
      if (mesh.layer[k] == region) order.push_back(k);
  append_items(sink, order.size(), [&](std::string& line, std::size_t id) {
    const auto& c = mesh.cells[order[id]];
    auto to = std::back_inserter(line);
    fmt::format_to(to, "{}", size_of(c) == 4 ? 9 : 5);
    for (int i = 0; i < size_of(c); ++i) fmt::format_to(to, " {}", c[static_cast<std::size_t>(i)]);
    fmt::format_to(to, " {}\n", id);
  });
  out += fmt::format("NPOIN= {}\n", mesh.points.size());
  append_items(sink, mesh.points.size(), [&mesh](std::string& line, std::size_t i) {
    append_point(line, mesh.points[i]);
    fmt::format_to(std::back_inserter(line), " {}\n", i);
  });
  // One marker per curve or kept group over all its curves' edges (su2_writer), in the order of their
  // tags; the edges of a marker in mesh order.
  const CurveTags tags = curve_tags(curves);
  std::vector<std::vector<std::size_t>> per_group(tags.groups.size());
  for (std::size_t k = 0; k < mesh.boundary_edges.size(); ++k) {
    const long long tag = tags.of_curve[static_cast<std::size_t>(mesh.boundary_edges[k].curve)];
    per_group[tags.group_of_tag(tag)].push_back(k);
  }
  out += fmt::format("NMARK= {}\n", tags.groups.size());
  for (std::size_t g = 0; g < per_group.size(); ++g) {
    out += fmt::format("MARKER_TAG= {}\nMARKER_ELEMS= {}\n", writable_name(tags.groups[g].name, true),
                       per_group[g].size());
    for (const std::size_t k : per_group[g]) {
      fmt::format_to(std::back_inserter(out), "3 {} {}\n", mesh.boundary_edges[k].a, mesh.boundary_edges[k].b);
      sink.piece_done();
    }
  }
}

}  // namespace

MixedSurfaces mixed_surfaces(const MixedMesh& mesh, long long first) {
  // The core's cells as a triangle mesh with their attributes, for region_surfaces' names and tags.
  Mesh core;
  std::vector<std::size_t> core_cells;
  for (std::size_t k = 0; k < mesh.cells.size(); ++k) {
    if (mesh.layer[k] != 0) continue;
    core_cells.push_back(k);
    core.triangles.push_back({mesh.cells[k][0], mesh.cells[k][1], mesh.cells[k][2]});
    if (mesh.region.size() == mesh.cells.size()) core.region.push_back(mesh.region[k]);
  }
  core.region_names = mesh.region_names;
  MixedSurfaces s;
  s.core = region_surfaces(core, first);
  const std::size_t ns = s.core.names.size();
  s.layer_tag = first + static_cast<long long>(ns);
  while (std::find(s.core.tags.begin(), s.core.tags.end(), s.layer_tag) != s.core.tags.end()) ++s.layer_tag;
  s.of_cell.assign(mesh.cells.size(), static_cast<int>(ns));
  for (std::size_t i = 0; i < core_cells.size(); ++i) s.of_cell[core_cells[i]] = s.core.of_triangle[i];
  return s;
}

std::string mixed_msh41_string(const MixedMesh& mesh, const std::vector<PeriodicLink>* periodic) {
  TextSink sink;
  write_mixed_msh41(mesh, sink, periodic);
  return sink.take();
}

std::string mixed_vtu_string(const MixedMesh& mesh) {
  TextSink sink;
  write_mixed_vtu(mesh, sink);
  return sink.take();
}

std::string mixed_su2_string(const MixedMesh& mesh) {
  TextSink sink;
  write_mixed_su2(mesh, sink);
  return sink.take();
}

const std::vector<std::string>& mixed_mesh_format_names() {
  static const std::vector<std::string> names = {"msh", "vtu", "su2", "mesh", "openfoam", "cgns"};
  return names;
}

bool is_mixed_mesh_format(const std::string& format) {
  const auto& names = mixed_mesh_format_names();
  return std::find(names.begin(), names.end(), format) != names.end();
}

std::vector<std::filesystem::path> write_mixed_mesh(const MixedMesh& mesh, const std::filesystem::path& dir,
                                                    const std::string& stem, const std::vector<std::string>& formats,
                                                    const std::vector<PeriodicLink>* periodic,
                                                    const std::vector<std::string>& walls) {
  for (const std::string& f : formats)
    if (!is_mixed_mesh_format(f))
      throw InputError(fmt::format("output.formats: '{}' cannot hold a boundary-layer mesh ({} can)", f,
                                   fmt::join(mixed_mesh_format_names(), ", ")));
  std::vector<std::filesystem::path> written;
  for (const std::string& f : formats) {
    if (f == "openfoam") {
      // With regions, the cells' subdomains as cellZones, named as the MSH file names them.
      const MixedSurfaces surfaces = mixed_surfaces(mesh, 1);
      OpenFoamZones zones{surfaces.core.names, surfaces.of_cell};
      zones.names.push_back(kLayerRegion);
      for (auto& p :
           write_openfoam(mesh, dir, stem, walls, mesh.curve_groups, surfaces.core.regions() ? &zones : nullptr))
        written.push_back(std::move(p));
      continue;
    }
    if (f == "cgns") {
      const std::filesystem::path path = dir / (stem + mesh_format_extensions(f).front());
      const MixedSurfaces surfaces = mixed_surfaces(mesh, 1);
      CgnsRegions regions{surfaces.core.names, surfaces.of_cell};
      regions.names.push_back(kLayerRegion);
      write_cgns(mesh, path, walls, mesh.curve_groups, surfaces.core.regions() ? &regions : nullptr);
      written.push_back(path);
      continue;
    }
    const std::filesystem::path path = dir / (stem + mesh_format_extensions(f).front());
    write_text_atomically(path, [&](TextSink& sink) {
      if (f == "msh")
        write_mixed_msh41(mesh, sink, periodic);
      else if (f == "vtu")
        write_mixed_vtu(mesh, sink);
      else if (f == "mesh")
        write_mixed_medit(mesh, sink);
      else
        write_mixed_su2(mesh, sink);
    });
    written.push_back(path);
  }
  return written;
}

Mesh boundary_of(const MixedMesh& mesh) {
  Mesh out = curves_of(mesh);
  out.points = mesh.points;
  return out;
}

MixedMesh mixed_mesh_of(const Mesh& mesh, const SurfaceCells& cells) {
  MixedMesh m;
  m.points = mesh.points;
  m.boundary_edges = mesh.boundary_edges;
  m.curve_names = mesh.curve_names;
  m.curve_groups = mesh.curve_groups;
  m.cells.reserve(mesh.triangles.size() + cells.quads.size());
  for (std::size_t i = 0; i < mesh.triangles.size(); ++i) {
    const auto& t = mesh.triangles[i];
    m.cells.push_back({t[0], t[1], t[2], -1});
    m.layer.push_back(cells.region_found ? cells.triangle_in_region[i] : 0);
  }
  for (std::size_t i = 0; i < cells.quads.size(); ++i) {
    m.cells.push_back(cells.quads[i]);
    m.layer.push_back(cells.region_found ? cells.quad_in_region[i] : 1);
  }
  return m;
}

void add_file_regions(MixedMesh& mixed, const Mesh& mesh) {
  if (mesh.region.empty() || mesh.region.size() != mesh.triangles.size()) return;
  mixed.region = mesh.region;
  mixed.region.resize(mixed.cells.size(), 0.0);
  mixed.region_names = mesh.region_names;
}

Mesh triangulated(const MixedMesh& mesh) {
  Mesh out;
  out.points = mesh.points;
  out.boundary_edges = mesh.boundary_edges;
  out.curve_names = mesh.curve_names;
  out.triangles.reserve(mesh.cells.size() + mesh.quads());
  for (const auto& c : mesh.cells) {
    if (c[3] < 0) {
      out.triangles.push_back({c[0], c[1], c[2]});
      continue;
    }
    const auto p = [&](int i) { return mesh.points[static_cast<std::size_t>(c[static_cast<std::size_t>(i)])]; };
    if (dist(p(0), p(2)) <= dist(p(1), p(3))) {
      out.triangles.push_back({c[0], c[1], c[2]});
      out.triangles.push_back({c[0], c[2], c[3]});
    } else {
      out.triangles.push_back({c[0], c[1], c[3]});
      out.triangles.push_back({c[1], c[2], c[3]});
    }
  }
  return out;
}

void add_layer_regions(const MixedMesh& mesh, Mesh& drawn) {
  // Attribute j + 1 for the j-th of the mixed_surfaces' core surfaces ("domain" without regions), the
  // next for the layer, named as the MSH file names them.
  const MixedSurfaces surfaces = mixed_surfaces(mesh, 1);
  drawn.region.clear();
  drawn.region.reserve(drawn.triangles.size());
  for (std::size_t k = 0; k < mesh.cells.size(); ++k) {
    const double attribute = surfaces.of_cell[k] + 1.0;
    drawn.region.push_back(attribute);
    if (mesh.cells[k][3] >= 0) drawn.region.push_back(attribute);  // a quad is two triangles
  }
  drawn.region_names.clear();
  for (std::size_t j = 0; j < surfaces.core.names.size(); ++j)
    drawn.region_names.push_back({static_cast<double>(j) + 1.0, surfaces.core.names[j]});
  drawn.region_names.push_back({static_cast<double>(surfaces.core.names.size()) + 1.0, kLayerRegion});
}

Mesh with_quads_split(Mesh mesh, const SurfaceCells& cells) {
  if (cells.quads.empty()) return mesh;
  MixedMesh quads;
  quads.points = mesh.points;
  quads.cells = cells.quads;
  for (const auto& t : triangulated(quads).triangles) mesh.triangles.push_back(t);
  return mesh;
}

}  // namespace pdmesh
