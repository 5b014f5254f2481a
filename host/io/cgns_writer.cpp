// CGNS writer (io/cgns_writer.hpp).
// Format: CGNS Standard Interface Data Structures (SIDS) and the CGNS Mid-Level Library, version
// 3.4 (https://cgns.github.io/CGNS_docs_current/): CGNSBase_t, Zone_t, GridCoordinates_t,
// Elements_t, ZoneBC_t / BC_t, Family_t. Readers consulted for the conventions: Gmsh 4.15 takes a
// zone's elements into named entities only through BC_t (EdgeCenter or CellCenter in a 2-D zone) and
// physical groups from the FamilyName children of Family_t; SU2 takes each lower-dimensional section
// as a marker named after the section.
#include "io/cgns_writer.hpp"

#include <algorithm>
#include <cstdint>
#include <limits>
#include <set>

#include <cgnslib.h>
#include <fmt/format.h>

#include "core/atomic_file.hpp"
#include "core/errors.hpp"
#include "core/interrupt.hpp"
#include "io/mesh_io_common.hpp"

namespace pdmesh {

namespace {

// CGNS node names hold at most 32 characters and no '/' (the path separator inside the file).
constexpr std::size_t kMaxName = 32;

// Names unique among the nodes that share a parent; the layout gives each group and region one name
// for its family, its BC and its sections, so it is made unique against all three parents' children.
class UniqueNames {
 public:
  UniqueNames() {
    // The fixed children of CGNSBase_t and Zone_t that a group's or region's name must not take.
    for (const char* n : {"Base", "Zone", "About", "ZoneType", "GridCoordinates", "ZoneBC", "FamilyName", "Regions",
                          "FlowSolution", "ZoneGridConnectivity", "FamBC", "DataClass"})
      taken_.insert(n);
  }
  std::string take(std::string name) {
    for (char& c : name)
      if (c == '/') c = '_';
    if (name.empty()) name = "unnamed";
    std::string out = fit(name, kMaxName);
    for (int k = 2; taken_.count(out) != 0; ++k) {
      const std::string suffix = fmt::format("_{}", k);
      out = fit(name, kMaxName - suffix.size()) + suffix;
    }
    taken_.insert(out);
    return out;
  }

 private:
  // `name` cut to at most `n` bytes, not inside a UTF-8 sequence.
  static std::string fit(const std::string& name, std::size_t n) {
    if (name.size() <= n) return name;
    std::size_t end = n;
    while (end > 0 && (static_cast<unsigned char>(name[end]) & 0xC0) == 0x80) --end;
    return name.substr(0, end);
  }
  std::set<std::string> taken_;
};

int corners(const std::array<int, 4>& c) { return c[3] < 0 ? 3 : 4; }

// An open CGNS file, closed on every way out; `check` turns a library failure into InputError naming
// the destination (not the temporary the library writes) and the library's own message.
class CgnsFile {
 public:
  CgnsFile(const std::filesystem::path& tmp, std::filesystem::path shown) : shown_(std::move(shown)) {
    check(cg_set_file_type(CG_FILE_HDF5), "selecting the HDF5 file type");
    check(cg_open(tmp.c_str(), CG_MODE_WRITE, &fn_), "opening the file for writing");
    open_ = true;
  }
  CgnsFile(const CgnsFile&) = delete;
  CgnsFile& operator=(const CgnsFile&) = delete;
  ~CgnsFile() {
    if (open_) cg_close(fn_);
  }
  int fn() const { return fn_; }
  void check(int status, const std::string& what) const {
    if (status != CG_OK)
      throw InputError(fmt::format("{}: CGNS library failed {}: {}", shown_.string(), what, cg_get_error()));
  }
  void close() {
    open_ = false;
    check(cg_close(fn_), "closing the file");
  }

 private:
  std::filesystem::path shown_;
  int fn_ = 0;
  bool open_ = false;
};

}  // namespace

CgnsLayout cgns_layout(const MixedMesh& mesh, const std::vector<std::string>& walls,
                       const std::vector<CurveGroupTag>& groups, const CgnsRegions* regions) {
  CgnsLayout layout;
  UniqueNames names;
  // The regions' cells, triangles then quadrilaterals, each in mesh order.
  std::vector<std::string> region_names = {kCoreRegion, kLayerRegion};
  std::vector<int> of_cell(mesh.cells.size());
  if (regions != nullptr) {
    region_names = regions->names;
    of_cell = regions->of_cell;
  } else {
    for (std::size_t k = 0; k < mesh.cells.size(); ++k) of_cell[k] = mesh.layer[k] != 0 ? 1 : 0;
  }
  if (of_cell.size() != mesh.cells.size())
    throw InputError(fmt::format("CGNS writer: {} region indices for {} cells", of_cell.size(), mesh.cells.size()));
  std::vector<std::vector<std::size_t>> tris(region_names.size()), quads(region_names.size());
  for (std::size_t k = 0; k < mesh.cells.size(); ++k) {
    const int r = of_cell[k];
    if (r < 0 || static_cast<std::size_t>(r) >= region_names.size())
      throw InputError(fmt::format("CGNS writer: cell {} has region index {} (of {})", k, r, region_names.size()));
    (corners(mesh.cells[k]) == 4 ? quads : tris)[static_cast<std::size_t>(r)].push_back(k);
  }
  // The curve groups' edges, as the SU2 markers: in the order of the tags, each in mesh order.
  Mesh curves;
  curves.boundary_edges = mesh.boundary_edges;
  curves.curve_names = mesh.curve_names;
  curves.curve_groups = groups;
  const CurveTags tags = curve_tags(curves);
  std::vector<std::vector<std::size_t>> per_group(tags.groups.size());
  for (std::size_t e = 0; e < mesh.boundary_edges.size(); ++e) {
    const int c = mesh.boundary_edges[e].curve;
    if (c < 0 || static_cast<std::size_t>(c) >= mesh.curve_names.size())
      throw InputError(
          fmt::format("CGNS writer: boundary edge {} is on curve {} (of {})", e, c, mesh.curve_names.size()));
    per_group[tags.group_of_tag(tags.of_curve[static_cast<std::size_t>(c)])].push_back(e);
  }
  const auto named_wall = [&](const std::string& name) {
    return std::find(walls.begin(), walls.end(), name) != walls.end();
  };
  // Names: the regions first (they hold the cells), then the groups.
  std::vector<std::string> region_node(region_names.size());
  for (std::size_t r = 0; r < region_names.size(); ++r) {
    if (tris[r].empty() && quads[r].empty()) continue;
    region_node[r] = names.take(writable_name(region_names[r], true));
  }
  std::vector<std::string> group_node(tags.groups.size());
  for (std::size_t g = 0; g < tags.groups.size(); ++g)
    group_node[g] = names.take(writable_name(tags.groups[g].name, true));

  std::size_t region_count = 0;
  for (std::size_t r = 0; r < region_names.size(); ++r) {
    if (region_node[r].empty()) continue;
    const bool both = !tris[r].empty() && !quads[r].empty();
    CgnsLayout::Boundary bc{region_node[r],         region_node[r], false,         true,
                            layout.sections.size(), both ? 2u : 1u, region_count++};
    if (!tris[r].empty())
      layout.sections.push_back({both ? names.take(region_node[r] + "_tri") : region_node[r], false, 3, tris[r]});
    if (!quads[r].empty())
      layout.sections.push_back({both ? names.take(region_node[r] + "_quad") : region_node[r], false, 4, quads[r]});
    layout.boundaries.push_back(std::move(bc));
  }
  std::vector<CgnsLayout::Boundary> group_bcs;
  for (std::size_t g = 0; g < tags.groups.size(); ++g) {
    const CurveTags::Group& group = tags.groups[g];
    const bool wall = named_wall(group.name) || std::any_of(group.curves.begin(), group.curves.end(), [&](int c) {
                        return named_wall(mesh.curve_names[static_cast<std::size_t>(c)]);
                      });
    layout.families.push_back({group_node[g], wall});
    if (per_group[g].empty()) continue;
    group_bcs.push_back({group_node[g], group_node[g], wall, false, layout.sections.size(), 1, 0});
    layout.sections.push_back({group_node[g], true, 2, per_group[g]});
  }
  for (std::size_t r = 0; r < region_names.size(); ++r)
    if (!region_node[r].empty()) layout.families.push_back({region_node[r], false});
  // The curve groups' BCs first: the boundary conditions a solver looks for.
  group_bcs.insert(group_bcs.end(), layout.boundaries.begin(), layout.boundaries.end());
  layout.boundaries = std::move(group_bcs);
  return layout;
}

void write_cgns(const MixedMesh& mesh, const std::filesystem::path& path, const std::vector<std::string>& walls,
                const std::vector<CurveGroupTag>& groups, const CgnsRegions* regions) {
  const CgnsLayout layout = cgns_layout(mesh, walls, groups, regions);
  // Debian's library indexes points and elements with 32-bit cgsize_t.
  const std::size_t elements = mesh.cells.size() + mesh.boundary_edges.size();
  if (mesh.points.size() > static_cast<std::size_t>(std::numeric_limits<cgsize_t>::max()) ||
      elements > static_cast<std::size_t>(std::numeric_limits<cgsize_t>::max()))
    throw LimitError(fmt::format("{}: {} points and {} elements are more than the CGNS library's indices hold ({})",
                                 path.string(), mesh.points.size(), elements, std::numeric_limits<cgsize_t>::max()));
  for (const auto& c : mesh.cells)
    for (int i = 0; i < corners(c); ++i)
      if (c[static_cast<std::size_t>(i)] < 0 ||
          static_cast<std::size_t>(c[static_cast<std::size_t>(i)]) >= mesh.points.size())
        throw InputError(fmt::format("CGNS writer: a cell refers to point {} (of {})", c[static_cast<std::size_t>(i)],
                                     mesh.points.size()));
  write_atomically(path, [&](const std::filesystem::path& tmp) {
    CgnsFile f(tmp, path);
    const int fn = f.fn();
    int base = 0, zone = 0;
    f.check(cg_base_write(fn, "Base", 2, 2, &base), "writing the base");
    f.check(cg_goto(fn, base, "end"), "going to the base");
    f.check(cg_descriptor_write("About", "Written by pdmesh"), "writing the base's descriptor");
    cgsize_t size[3] = {static_cast<cgsize_t>(mesh.points.size()), static_cast<cgsize_t>(mesh.cells.size()), 0};
    f.check(cg_zone_write(fn, base, "Zone", size, CGNS_ENUMV(Unstructured), &zone), "writing the zone");
    {
      std::vector<double> v(mesh.points.size());
      int c = 0;
      for (std::size_t i = 0; i < v.size(); ++i) v[i] = mesh.points[i].x;
      f.check(cg_coord_write(fn, base, zone, CGNS_ENUMV(RealDouble), "CoordinateX", v.data(), &c),
              "writing CoordinateX");
      for (std::size_t i = 0; i < v.size(); ++i) v[i] = mesh.points[i].y;
      f.check(cg_coord_write(fn, base, zone, CGNS_ENUMV(RealDouble), "CoordinateY", v.data(), &c),
              "writing CoordinateY");
    }
    // Element numbers run on through the sections from 1, in layout order.
    std::vector<cgsize_t> first(layout.sections.size());
    cgsize_t next = 1;
    for (std::size_t s = 0; s < layout.sections.size(); ++s) {
      check_interrupt();
      const CgnsLayout::Section& sec = layout.sections[s];
      std::vector<cgsize_t> conn;
      conn.reserve(sec.items.size() * static_cast<std::size_t>(sec.corners));
      for (const std::size_t k : sec.items) {
        if (sec.bar) {
          conn.push_back(mesh.boundary_edges[k].a + 1);
          conn.push_back(mesh.boundary_edges[k].b + 1);
        } else {
          for (int i = 0; i < sec.corners; ++i) conn.push_back(mesh.cells[k][static_cast<std::size_t>(i)] + 1);
        }
      }
      const auto type = sec.bar ? CGNS_ENUMV(BAR_2) : sec.corners == 4 ? CGNS_ENUMV(QUAD_4) : CGNS_ENUMV(TRI_3);
      first[s] = next;
      const cgsize_t last = next + static_cast<cgsize_t>(sec.items.size()) - 1;
      int index = 0;
      f.check(cg_section_write(fn, base, zone, sec.name.c_str(), type, next, last, 0, conn.data(), &index),
              fmt::format("writing the element section '{}'", sec.name));
      next = last + 1;
    }
    // The regions as cell data too: a reader that merges the cell sections (ParaView's "Internal"
    // block) colours and thresholds by it. Cell c's value is the index of its region's section among
    // the regions, in file order; the cells are numbered as the sections number them.
    {
      std::vector<double> region(mesh.cells.size());
      std::size_t cell = 0;
      for (const CgnsLayout::Boundary& b : layout.boundaries) {
        if (!b.cells) continue;
        const double value = static_cast<double>(b.region);
        for (std::size_t s = b.section; s < b.section + b.sections; ++s)
          for (std::size_t k = 0; k < layout.sections[s].items.size(); ++k) region[cell++] = value;
      }
      int solution = 0, field = 0;
      f.check(cg_sol_write(fn, base, zone, "Regions", CGNS_ENUMV(CellCenter), &solution), "writing the region data");
      f.check(cg_field_write(fn, base, zone, solution, CGNS_ENUMV(RealDouble), "region", region.data(), &field),
              "writing the region data");
    }
    for (const CgnsLayout::Boundary& b : layout.boundaries) {
      const CgnsLayout::Section& sec = layout.sections[b.section];
      int index = 0;
      const std::string what = fmt::format("writing the boundary condition '{}'", b.name);
      if (b.cells) {
        // A region's sections are adjacent: its cells are one range of element numbers.
        const CgnsLayout::Section& end = layout.sections[b.section + b.sections - 1];
        cgsize_t range[2] = {first[b.section],
                             first[b.section + b.sections - 1] + static_cast<cgsize_t>(end.items.size()) - 1};
        f.check(cg_boco_write(fn, base, zone, b.name.c_str(), CGNS_ENUMV(FamilySpecified), CGNS_ENUMV(PointRange), 2,
                              range, &index),
                what);
      } else {
        std::vector<cgsize_t> list(sec.items.size());
        for (std::size_t i = 0; i < list.size(); ++i) list[i] = first[b.section] + static_cast<cgsize_t>(i);
        f.check(cg_boco_write(fn, base, zone, b.name.c_str(), CGNS_ENUMV(FamilySpecified), CGNS_ENUMV(PointList),
                              static_cast<cgsize_t>(list.size()), list.data(), &index),
                what);
      }
      f.check(
          cg_boco_gridlocation_write(fn, base, zone, index, b.cells ? CGNS_ENUMV(CellCenter) : CGNS_ENUMV(EdgeCenter)),
          what);
      f.check(cg_goto(fn, base, "Zone_t", zone, "ZoneBC_t", 1, "BC_t", index, "end"), what);
      f.check(cg_famname_write(b.family.c_str()), what);
    }
    for (const CgnsLayout::Family& family_of : layout.families) {
      const std::string& name = family_of.name;
      const bool wall = family_of.wall;
      const std::string what = fmt::format("writing the family '{}'", name);
      int family = 0, fambc = 0;
      f.check(cg_family_write(fn, base, name.c_str(), &family), what);
      f.check(cg_fambc_write(fn, base, family, "FamBC", wall ? CGNS_ENUMV(BCWall) : CGNS_ENUMV(BCTypeNull), &fambc),
              what);
      f.check(cg_family_name_write(fn, base, family, "FamilyName", name.c_str()), what);
    }
    f.close();
  });
}

}  // namespace pdmesh
