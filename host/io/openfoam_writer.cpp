// OpenFOAM polyMesh writer.
// Format: OpenFOAM User Guide, "Mesh description" (section 5.1 of the v1912 guide): points
// (vectorField), faces (faceList), owner and neighbour (labelList), boundary (polyBoundaryMesh);
// each file a FoamFile header, then N, "(", the entries, ")".
#include "io/openfoam_writer.hpp"

#include <algorithm>
#include <cstdint>
#include <iterator>

#include <fmt/format.h>

#include "core/errors.hpp"
#include "core/interrupt.hpp"
#include "io/text_file.hpp"

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

OpenFoamFiles openfoam_files(const MixedMesh& mesh, const std::vector<std::string>& walls,
                             const std::vector<CurveGroupTag>& groups, const OpenFoamZones* zones, double thickness) {
  const std::size_t n = mesh.points.size();
  Mesh curves = boundary_of(mesh);
  curves.curve_groups = groups;
  check_mesh_for_writing(curves, "OpenFOAM writer");
  const CurveTags tags = curve_tags(curves);
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

  // Internal faces (owner, neighbour, owner's side) and border sides by curve.
  struct Internal {
    int owner, neighbour, a, b;
  };
  std::vector<Internal> internal;
  std::vector<std::uint64_t> edge_keys(mesh.boundary_edges.size());
  std::vector<std::size_t> edge_order(mesh.boundary_edges.size());
  for (std::size_t e = 0; e < mesh.boundary_edges.size(); ++e) {
    edge_keys[e] = side_key(mesh.boundary_edges[e].a, mesh.boundary_edges[e].b);
    edge_order[e] = e;
  }
  std::sort(edge_order.begin(), edge_order.end(),
            [&](std::size_t x, std::size_t y) { return edge_keys[x] < edge_keys[y]; });
  std::vector<std::vector<Side>> per_patch(tags.groups.size());
  for (std::size_t i = 0; i < sides.size();) {
    std::size_t j = i + 1;
    while (j < sides.size() && sides[j].key == sides[i].key) ++j;
    if (j - i > 2) {
      throw InputError(
          fmt::format("OpenFOAM writer: the side {}-{} belongs to {} cells", sides[i].a, sides[i].b, j - i));
    }
    if (j - i == 2) {
      internal.push_back({sides[i].cell, sides[i + 1].cell, sides[i].a, sides[i].b});  // sorted: owner first
    } else {
      const auto it = std::lower_bound(edge_order.begin(), edge_order.end(), sides[i].key,
                                       [&](std::size_t e, std::uint64_t key) { return edge_keys[e] < key; });
      if (it == edge_order.end() || edge_keys[*it] != sides[i].key) {
        throw InputError(
            fmt::format("OpenFOAM writer: the side {}-{} of cell {} is on the mesh's border but on no curve",
                        sides[i].a, sides[i].b, sides[i].cell));
      }
      const long long tag = tags.of_curve[static_cast<std::size_t>(mesh.boundary_edges[*it].curve)];
      per_patch[tags.group_of_tag(tag)].push_back(sides[i]);
    }
    i = j;
  }
  std::sort(internal.begin(), internal.end(), [](const Internal& x, const Internal& y) {
    return x.owner != y.owner ? x.owner < y.owner : x.neighbour < y.neighbour;
  });
  for (auto& list : per_patch)
    std::sort(list.begin(), list.end(), [](const Side& x, const Side& y) { return x.cell < y.cell; });

  OpenFoamFiles files;
  auto points = std::back_inserter(files.points);
  files.points = header("vectorField", "points") + fmt::format("{}\n(\n", 2 * n);
  for (int layer = 0; layer < 2; ++layer) {
    const double z = layer == 0 ? 0.0 : thickness;
    for (std::size_t i = 0; i < n; ++i) {
      if ((i & 65535) == 0) check_interrupt();
      fmt::format_to(points, "({:.17g} {:.17g} {:.17g})\n", mesh.points[i].x, mesh.points[i].y, z);
    }
  }
  files.points += ")\n";

  std::size_t boundary_faces = 2 * mesh.cells.size();
  for (const auto& list : per_patch) boundary_faces += list.size();
  const std::size_t faces = internal.size() + boundary_faces;
  const std::string note = fmt::format("nPoints: {} nCells: {} nFaces: {} nInternalFaces: {}", 2 * n, mesh.cells.size(),
                                       faces, internal.size());
  files.faces = header("faceList", "faces") + fmt::format("{}\n(\n", faces);
  files.owner = header("labelList", "owner");
  files.owner.insert(files.owner.find("    location"), fmt::format("    note        \"{}\";\n", note));
  files.owner += fmt::format("{}\n(\n", faces);
  files.neighbour = header("labelList", "neighbour");
  files.neighbour.insert(files.neighbour.find("    location"), fmt::format("    note        \"{}\";\n", note));
  files.neighbour += fmt::format("{}\n(\n", internal.size());
  auto owner = std::back_inserter(files.owner);
  auto neighbour = std::back_inserter(files.neighbour);
  for (const Internal& f : internal) {
    side_face(files.faces, f.a, f.b, n);
    fmt::format_to(owner, "{}\n", f.owner);
    fmt::format_to(neighbour, "{}\n", f.neighbour);
  }
  files.neighbour += ")\n";

  // The patches: one per curve or group, then the front and back.
  std::string patches;
  std::size_t start = internal.size();
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
  for (std::size_t g = 0; g < per_patch.size(); ++g) {
    for (const Side& s : per_patch[g]) {
      side_face(files.faces, s.a, s.b, n);
      fmt::format_to(owner, "{}\n", s.cell);
    }
    const CurveTags::Group& group = tags.groups[g];
    const bool wall = named(group.name) || std::any_of(group.curves.begin(), group.curves.end(), [&](int c) {
                        return named(mesh.curve_names[static_cast<std::size_t>(c)]);
                      });
    patch(writable_name(group.name, true), wall ? "wall" : "patch", per_patch[g].size());
  }
  // Front (z = 0, normal -z: the cell's corners clockwise) and back (z = thickness, counter-clockwise).
  auto face_out = std::back_inserter(files.faces);
  for (std::size_t c = 0; c < mesh.cells.size(); ++c) {
    const auto& cell = mesh.cells[c];
    if (corners(cell) == 3)
      fmt::format_to(face_out, "3({} {} {})\n", cell[2], cell[1], cell[0]);
    else
      fmt::format_to(face_out, "4({} {} {} {})\n", cell[3], cell[2], cell[1], cell[0]);
    fmt::format_to(owner, "{}\n", c);
  }
  for (std::size_t c = 0; c < mesh.cells.size(); ++c) {
    const auto& cell = mesh.cells[c];
    if (corners(cell) == 3)
      fmt::format_to(face_out, "3({} {} {})\n", cell[0] + n, cell[1] + n, cell[2] + n);
    else
      fmt::format_to(face_out, "4({} {} {} {})\n", cell[0] + n, cell[1] + n, cell[2] + n, cell[3] + n);
    fmt::format_to(owner, "{}\n", c);
  }
  patch("frontAndBack", "empty", 2 * mesh.cells.size());
  files.faces += ")\n";
  files.owner += ")\n";
  files.boundary = header("polyBoundaryMesh", "boundary") + fmt::format("{}\n(\n{})\n", per_patch.size() + 1, patches);
  if (zones != nullptr) {
    if (zones->of_cell.size() != mesh.cells.size())
      throw InputError(
          fmt::format("OpenFOAM writer: {} zone indices for {} cells", zones->of_cell.size(), mesh.cells.size()));
    std::vector<std::vector<std::size_t>> members(zones->names.size());
    for (std::size_t c = 0; c < mesh.cells.size(); ++c) {
      const int z = zones->of_cell[c];
      if (z < 0 || static_cast<std::size_t>(z) >= members.size())
        throw InputError(fmt::format("OpenFOAM writer: cell {} in zone {} of {}", c, z, members.size()));
      members[static_cast<std::size_t>(z)].push_back(c);
    }
    files.cell_zones = header("regIOobject", "cellZones") + fmt::format("{}\n(\n", members.size());
    auto out = std::back_inserter(files.cell_zones);
    for (std::size_t z = 0; z < members.size(); ++z) {
      fmt::format_to(out, "{}\n{{\n    type cellZone;\ncellLabels      List<label> \n{}\n(\n",
                     writable_name(zones->names[z], true), members[z].size());
      for (std::size_t c : members[z]) fmt::format_to(out, "{}\n", c);
      files.cell_zones += ")\n;\n}\n\n";
    }
    files.cell_zones += ")\n";
  }
  return files;
}

std::vector<std::filesystem::path> write_openfoam(const MixedMesh& mesh, const std::filesystem::path& dir,
                                                  const std::string& stem, const std::vector<std::string>& walls,
                                                  const std::vector<CurveGroupTag>& groups,
                                                  const OpenFoamZones* zones) {
  const OpenFoamFiles files = openfoam_files(mesh, walls, groups, zones);
  const std::filesystem::path root = dir / (stem + "_openfoam");
  const std::filesystem::path poly = root / "constant" / "polyMesh";
  std::error_code ec;
  std::filesystem::create_directories(poly, ec);
  if (ec) throw InputError(fmt::format("cannot create '{}': {}", poly.string(), ec.message()));
  std::vector<std::filesystem::path> written;
  const auto put = [&](const std::filesystem::path& path, const std::string& text) {
    write_text_file(path, text);
    written.push_back(path);
  };
  put(poly / "points", files.points);
  put(poly / "faces", files.faces);
  put(poly / "owner", files.owner);
  put(poly / "neighbour", files.neighbour);
  put(poly / "boundary", files.boundary);
  if (!files.cell_zones.empty()) put(poly / "cellZones", files.cell_zones);
  return written;
}

}  // namespace pdmesh
