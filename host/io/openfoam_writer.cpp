// OpenFOAM polyMesh writer.
// Format: OpenFOAM User Guide, "Mesh description" (section 5.1 of the v1912 guide): points
// (vectorField), faces (faceList), owner and neighbour (labelList), boundary (polyBoundaryMesh);
// each file a FoamFile header, then N, "(", the entries, ")".
#include "io/openfoam_writer.hpp"

#include <algorithm>
#include <cstdint>
#include <functional>
#include <iterator>

#include <fmt/format.h>

#include "core/errors.hpp"
#include "core/interrupt.hpp"
#include "core/text_sink.hpp"

namespace pdmesh {

namespace {

std::string header(const char* cls, const char* object) {
  return fmt::format(
      "/* Written by pdmesh */\n"
      "FoamFile\n{{\n    version     2.0;\n    format      ascii;\n    class       {};\n"
      "    location    \"constant/polyMesh\";\n    object      {};\n}}\n\n",
      cls, object);
}

int corners(const std::array<int, 4>& cell) { return cell[3] < 0 ? 3 : 4; }

// A cell side: its points in the cell's counter-clockwise order, and the cell.
struct Side {
  std::uint64_t key;  // the two points, the lower first
  int cell;
  int a, b;
};

std::uint64_t side_key(int a, int b) {
  const auto lo = static_cast<std::uint64_t>(static_cast<std::uint32_t>(std::min(a, b)));
  const auto hi = static_cast<std::uint64_t>(static_cast<std::uint32_t>(std::max(a, b)));
  return (lo << 32) | hi;
}

// The side face of a 2-D edge a -> b whose cell lies on its left: bottom a, bottom b, top b, top a,
// whose normal (right-hand rule) points to the edge's right, out of that cell.
void side_face(std::string& out, int a, int b, std::size_t n) {
  fmt::format_to(std::back_inserter(out), "4({} {} {} {})\n", a, b, static_cast<std::size_t>(b) + n,
                 static_cast<std::size_t>(a) + n);
}

}  // namespace

namespace {

struct Internal {
  int owner, neighbour, a, b;  // a -> b: the owner's side, counter-clockwise in the owner
};

// The faces' order and patches, found once for all the files: internal faces by owner and
// neighbour, border sides by patch (by cell within one).
struct FoamTopology {
  Mesh curves;  // the curves, boundary edges and groups (for curve_tags and the checks)
  CurveTags tags;
  std::vector<Internal> internal;
  std::vector<std::vector<Side>> per_patch;
  std::size_t faces = 0;
};

FoamTopology foam_topology(const MixedMesh& mesh, const std::vector<CurveGroupTag>& groups) {
  const std::size_t n = mesh.points.size();
  FoamTopology t;
  t.curves = boundary_of(mesh);
  t.curves.curve_groups = groups;
  check_mesh_for_writing(t.curves, "OpenFOAM writer");
  t.tags = curve_tags(t.curves);
  for (std::size_t c = 0; c < mesh.cells.size(); ++c)
    for (int k = 0; k < corners(mesh.cells[c]); ++k)
      if (mesh.cells[c][k] < 0 || static_cast<std::size_t>(mesh.cells[c][k]) >= n)
        throw InputError(fmt::format("OpenFOAM writer: cell {} has point index {} of {}", c, mesh.cells[c][k], n));

  // Every cell side, sorted by its points: two entries for an internal side, one on the border.
  std::vector<Side> sides;
  sides.reserve(4 * mesh.cells.size());
  for (std::size_t c = 0; c < mesh.cells.size(); ++c) {
    const int m = corners(mesh.cells[c]);
    for (int k = 0; k < m; ++k) {
      const int a = mesh.cells[c][k], b = mesh.cells[c][(k + 1) % m];
      sides.push_back({side_key(a, b), static_cast<int>(c), a, b});
    }
  }
  std::sort(sides.begin(), sides.end(),
            [](const Side& x, const Side& y) { return x.key != y.key ? x.key < y.key : x.cell < y.cell; });

  std::vector<std::uint64_t> edge_keys(mesh.boundary_edges.size());
  std::vector<std::size_t> edge_order(mesh.boundary_edges.size());
  for (std::size_t e = 0; e < mesh.boundary_edges.size(); ++e) {
    edge_keys[e] = side_key(mesh.boundary_edges[e].a, mesh.boundary_edges[e].b);
    edge_order[e] = e;
  }
  std::sort(edge_order.begin(), edge_order.end(),
            [&](std::size_t x, std::size_t y) { return edge_keys[x] < edge_keys[y]; });
  t.per_patch.resize(t.tags.groups.size());
  for (std::size_t i = 0; i < sides.size();) {
    std::size_t j = i + 1;
    while (j < sides.size() && sides[j].key == sides[i].key) ++j;
    if (j - i > 2) {
      throw InputError(
          fmt::format("OpenFOAM writer: the side {}-{} belongs to {} cells", sides[i].a, sides[i].b, j - i));
    }
    if (j - i == 2) {
      t.internal.push_back({sides[i].cell, sides[i + 1].cell, sides[i].a, sides[i].b});  // sorted: owner first
    } else {
      const auto it = std::lower_bound(edge_order.begin(), edge_order.end(), sides[i].key,
                                       [&](std::size_t e, std::uint64_t key) { return edge_keys[e] < key; });
      if (it == edge_order.end() || edge_keys[*it] != sides[i].key) {
        throw InputError(
            fmt::format("OpenFOAM writer: the side {}-{} of cell {} is on the mesh's border but on no curve",
                        sides[i].a, sides[i].b, sides[i].cell));
      }
      const long long tag = t.tags.of_curve[static_cast<std::size_t>(mesh.boundary_edges[*it].curve)];
      t.per_patch[t.tags.group_of_tag(tag)].push_back(sides[i]);
    }
    i = j;
  }
  std::sort(t.internal.begin(), t.internal.end(), [](const Internal& x, const Internal& y) {
    return x.owner != y.owner ? x.owner < y.owner : x.neighbour < y.neighbour;
  });
  for (auto& list : t.per_patch)
    std::sort(list.begin(), list.end(), [](const Side& x, const Side& y) { return x.cell < y.cell; });
  t.faces = t.internal.size() + 2 * mesh.cells.size();
  for (const auto& list : t.per_patch) t.faces += list.size();
  return t;
}

// The zones' cells, ascending; throws InputError unless there is one zone index per cell.
std::vector<std::vector<std::size_t>> zone_members(const MixedMesh& mesh, const OpenFoamZones& zones) {
  if (zones.of_cell.size() != mesh.cells.size())
    throw InputError(
        fmt::format("OpenFOAM writer: {} zone indices for {} cells", zones.of_cell.size(), mesh.cells.size()));
  std::vector<std::vector<std::size_t>> members(zones.names.size());
  for (std::size_t c = 0; c < mesh.cells.size(); ++c) {
    const int z = zones.of_cell[c];
    if (z < 0 || static_cast<std::size_t>(z) >= members.size())
      throw InputError(fmt::format("OpenFOAM writer: cell {} in zone {} of {}", c, z, members.size()));
    members[static_cast<std::size_t>(z)].push_back(c);
  }
  return members;
}

void write_points(const MixedMesh& mesh, double thickness, TextSink& sink) {
  const std::size_t n = mesh.points.size();
  sink.text() += header("vectorField", "points") + fmt::format("{}\n(\n", 2 * n);
  for (int layer = 0; layer < 2; ++layer) {
    const double z = layer == 0 ? 0.0 : thickness;
    for (std::size_t i = 0; i < n; ++i) {
      if ((i & 65535) == 0) check_interrupt();
      fmt::format_to(std::back_inserter(sink.text()), "({:.17g} {:.17g} {:.17g})\n", mesh.points[i].x, mesh.points[i].y,
                     z);
      sink.piece_done();
    }
  }
  sink.text() += ")\n";
}

void write_faces(const MixedMesh& mesh, const FoamTopology& t, TextSink& sink) {
  const std::size_t n = mesh.points.size();
  std::string& out = sink.text();
  out += header("faceList", "faces") + fmt::format("{}\n(\n", t.faces);
  for (std::size_t i = 0; i < t.internal.size(); ++i) {
    if ((i & 65535) == 0) check_interrupt();
    side_face(out, t.internal[i].a, t.internal[i].b, n);
    sink.piece_done();
  }
  for (const auto& list : t.per_patch)
    for (const Side& s : list) {
      side_face(out, s.a, s.b, n);
      sink.piece_done();
    }
  // Front (z = 0, normal -z: the cell's corners clockwise) and back (z = thickness, counter-clockwise).
  auto to = std::back_inserter(out);
  for (int back = 0; back < 2; ++back) {
    for (std::size_t c = 0; c < mesh.cells.size(); ++c) {
      if ((c & 65535) == 0) check_interrupt();
      const auto& cell = mesh.cells[c];
      const std::size_t shift = back == 1 ? n : 0;
      const auto v = [&](int k) { return static_cast<std::size_t>(cell[static_cast<std::size_t>(k)]) + shift; };
      if (corners(cell) == 3) {
        if (back == 0)
          fmt::format_to(to, "3({} {} {})\n", v(2), v(1), v(0));
        else
          fmt::format_to(to, "3({} {} {})\n", v(0), v(1), v(2));
      } else {
        if (back == 0)
          fmt::format_to(to, "4({} {} {} {})\n", v(3), v(2), v(1), v(0));
        else
          fmt::format_to(to, "4({} {} {} {})\n", v(0), v(1), v(2), v(3));
      }
      sink.piece_done();
    }
  }
  out += ")\n";
}

std::string count_note(const MixedMesh& mesh, const FoamTopology& t) {
  return fmt::format("    note        \"nPoints: {} nCells: {} nFaces: {} nInternalFaces: {}\";\n",
                     2 * mesh.points.size(), mesh.cells.size(), t.faces, t.internal.size());
}

// A labelList header with the counts' note, as OpenFOAM's own owner and neighbour files have it.
std::string noted_header(const char* object, const MixedMesh& mesh, const FoamTopology& t) {
  std::string h = header("labelList", object);
  h.insert(h.find("    location"), count_note(mesh, t));
  return h;
}

void write_owner(const MixedMesh& mesh, const FoamTopology& t, TextSink& sink) {
  std::string& out = sink.text();
  out += noted_header("owner", mesh, t) + fmt::format("{}\n(\n", t.faces);
  auto to = std::back_inserter(out);
  for (std::size_t i = 0; i < t.internal.size(); ++i) {
    if ((i & 65535) == 0) check_interrupt();
    fmt::format_to(to, "{}\n", t.internal[i].owner);
    sink.piece_done();
  }
  for (const auto& list : t.per_patch)
    for (const Side& s : list) fmt::format_to(to, "{}\n", s.cell);
  for (int side = 0; side < 2; ++side)
    for (std::size_t c = 0; c < mesh.cells.size(); ++c) {
      fmt::format_to(to, "{}\n", c);
      sink.piece_done();
    }
  out += ")\n";
}

void write_neighbour(const MixedMesh& mesh, const FoamTopology& t, TextSink& sink) {
  std::string& out = sink.text();
  out += noted_header("neighbour", mesh, t) + fmt::format("{}\n(\n", t.internal.size());
  auto to = std::back_inserter(out);
  for (std::size_t i = 0; i < t.internal.size(); ++i) {
    if ((i & 65535) == 0) check_interrupt();
    fmt::format_to(to, "{}\n", t.internal[i].neighbour);
    sink.piece_done();
  }
  out += ")\n";
}

void write_boundary(const MixedMesh& mesh, const FoamTopology& t, const std::vector<std::string>& walls,
                    TextSink& sink) {
  std::string patches;
  std::size_t start = t.internal.size();
  const auto patch = [&](const std::string& name, const char* type, std::size_t count) {
    fmt::format_to(std::back_inserter(patches),
                   "    {}\n    {{\n        type            {};\n        inGroups        1({});\n"
                   "        nFaces          {};\n        startFace       {};\n    }}\n",
                   name, type, type, count, start);
    start += count;
  };
  const auto named = [&](const std::string& name) {
    return std::find(walls.begin(), walls.end(), name) != walls.end();
  };
  for (std::size_t g = 0; g < t.per_patch.size(); ++g) {
    const CurveTags::Group& group = t.tags.groups[g];
    const bool wall = named(group.name) || std::any_of(group.curves.begin(), group.curves.end(), [&](int c) {
                        return named(mesh.curve_names[static_cast<std::size_t>(c)]);
                      });
    patch(writable_name(group.name, true), wall ? "wall" : "patch", t.per_patch[g].size());
  }
  patch("frontAndBack", "empty", 2 * mesh.cells.size());
  sink.text() += header("polyBoundaryMesh", "boundary") + fmt::format("{}\n(\n{})\n", t.per_patch.size() + 1, patches);
}

void write_cell_zones(const OpenFoamZones& zones, const std::vector<std::vector<std::size_t>>& members,
                      TextSink& sink) {
  std::string& out = sink.text();
  out += header("regIOobject", "cellZones") + fmt::format("{}\n(\n", members.size());
  auto to = std::back_inserter(out);
  for (std::size_t z = 0; z < members.size(); ++z) {
    fmt::format_to(to, "{}\n{{\n    type cellZone;\ncellLabels      List<label> \n{}\n(\n",
                   writable_name(zones.names[z], true), members[z].size());
    for (std::size_t c : members[z]) {
      fmt::format_to(to, "{}\n", c);
      sink.piece_done();
    }
    out += ")\n;\n}\n\n";
  }
  out += ")\n";
}

template <class Write>
std::string as_text(Write&& write) {
  TextSink sink;
  write(sink);
  return sink.take();
}

}  // namespace

OpenFoamFiles openfoam_files(const MixedMesh& mesh, const std::vector<std::string>& walls,
                             const std::vector<CurveGroupTag>& groups, const OpenFoamZones* zones, double thickness) {
  const FoamTopology t = foam_topology(mesh, groups);
  OpenFoamFiles files;
  files.points = as_text([&](TextSink& s) { write_points(mesh, thickness, s); });
  files.faces = as_text([&](TextSink& s) { write_faces(mesh, t, s); });
  files.owner = as_text([&](TextSink& s) { write_owner(mesh, t, s); });
  files.neighbour = as_text([&](TextSink& s) { write_neighbour(mesh, t, s); });
  files.boundary = as_text([&](TextSink& s) { write_boundary(mesh, t, walls, s); });
  if (zones != nullptr) {
    const auto members = zone_members(mesh, *zones);
    files.cell_zones = as_text([&](TextSink& s) { write_cell_zones(*zones, members, s); });
  }
  return files;
}

std::filesystem::path openfoam_polymesh_dir(const std::filesystem::path& dir, const std::string& stem) {
  return dir / (stem + "_openfoam") / "constant" / "polyMesh";
}

const std::vector<std::string>& openfoam_file_names() {
  static const std::vector<std::string> names = {"points", "faces", "owner", "neighbour", "boundary", "cellZones"};
  return names;
}

std::vector<std::filesystem::path> write_openfoam(const MixedMesh& mesh, const std::filesystem::path& dir,
                                                  const std::string& stem, const std::vector<std::string>& walls,
                                                  const std::vector<CurveGroupTag>& groups,
                                                  const OpenFoamZones* zones) {
  // Every check before the first file: a refused mesh writes nothing.
  const FoamTopology t = foam_topology(mesh, groups);
  const auto members = zones != nullptr ? zone_members(mesh, *zones) : std::vector<std::vector<std::size_t>>{};
  const std::filesystem::path poly = openfoam_polymesh_dir(dir, stem);
  std::error_code ec;
  std::filesystem::create_directories(poly, ec);
  if (ec) throw InputError(fmt::format("cannot create '{}': {}", poly.string(), ec.message()));
  std::vector<std::filesystem::path> written;
  const auto put = [&](const char* name, const std::function<void(TextSink&)>& write) {
    write_text_atomically(poly / name, write);
    written.push_back(poly / name);
  };
  put("points", [&](TextSink& s) { write_points(mesh, 1.0, s); });
  put("faces", [&](TextSink& s) { write_faces(mesh, t, s); });
  put("owner", [&](TextSink& s) { write_owner(mesh, t, s); });
  put("neighbour", [&](TextSink& s) { write_neighbour(mesh, t, s); });
  put("boundary", [&](TextSink& s) { write_boundary(mesh, t, walls, s); });
  if (zones != nullptr) put("cellZones", [&](TextSink& s) { write_cell_zones(*zones, members, s); });
  return written;
}

}  // namespace pdmesh
