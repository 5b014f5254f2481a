// CGNS writer: the mesh as one unstructured zone of an HDF5-based CGNS file, through the CGNS
// library's mid-level API (cg_*), the standard mesh exchange of CFD codes (SU2, Fluent, STAR-CCM+,
// Pointwise, ParaView, Gmsh).
#pragma once
#include <filesystem>
#include <string>
#include <vector>

#include "io/mixed_mesh.hpp"

namespace pdmesh {

// The cells' subdomains as named sets: `names`, and per cell of the MixedMesh the index of its name.
struct CgnsRegions {
  std::vector<std::string> names;
  std::vector<int> of_cell;
};

// What write_cgns writes, in file order, for tests and messages: the element sections with their
// first and last element number (1-based, zone-wide), and the boundary conditions.
struct CgnsLayout {
  struct Section {
    std::string name;
    bool bar = false;                // BAR_2 (a boundary group's edges); else cells
    int corners = 3;                 // 3 (TRI_3), 4 (QUAD_4) or 2 (BAR_2)
    std::vector<std::size_t> items;  // cells (MixedMesh::cells indices) or boundary edges, in order
  };
  struct Boundary {
    std::string name, family;
    bool wall = false;
    bool cells = false;       // a region's cells (CellCenter) rather than a curve group's edges (EdgeCenter)
    std::size_t section = 0;  // for a curve group: its BAR_2 section; a region: its first section
    std::size_t sections = 1;
    std::size_t region = 0;  // a region's index among the regions, in file order (its cells' "region" value)
  };
  std::vector<Section> sections;
  std::vector<Boundary> boundaries;
  struct Family {
    std::string name;
    bool wall = false;  // FamilyBC BCWall, else BCTypeNull
  };
  std::vector<Family> families;  // one per curve group (also those without edges), then per region
};

// The file's layout: per region (`regions`, or "domain" and "boundary_layer" by MixedMesh::layer when
// null) its triangles, then its quadrilaterals, each a section named after the region (NAME_tri and
// NAME_quad when it has both); then one BAR_2 section per curve, or per physical group of curves
// (`groups`, Mesh::curve_groups) in the order of their tags (curve_tags, as the SU2 markers), named
// as the SU2 markers. A group without edges has a family but no section. Names are at most 32
// characters (CGNS's limit) and unique among their siblings.
CgnsLayout cgns_layout(const MixedMesh& mesh, const std::vector<std::string>& walls,
                       const std::vector<CurveGroupTag>& groups = {}, const CgnsRegions* regions = nullptr);

// Writes `path` atomically (a temporary beside it, then rename): base "Base" (cell and physical
// dimension 2; no units or data class: the geometry's units are not known), zone "Zone"
// (Unstructured) with CoordinateX/Y (double), the sections of cgns_layout, a cell-centred
// FlowSolution "Regions" with the field "region" (each cell's region index, in file order), a ZoneBC
// with one BC_t per curve group (PointList of its BAR_2 elements, GridLocation EdgeCenter) and one per
// region (PointRange of its cells, GridLocation CellCenter), each of type FamilySpecified with a
// FamilyName; and one Family_t per curve group and region with its FamilyBC (BCWall where `walls`
// names the group or one of its curves, else BCTypeNull) and, as Gmsh reads physical groups, a
// FamilyName child holding its own name. Throws InputError naming the file and the CGNS library's
// message when the library fails, LimitError when the mesh has more points or elements than the
// library's 32-bit indices hold.
void write_cgns(const MixedMesh& mesh, const std::filesystem::path& path, const std::vector<std::string>& walls,
                const std::vector<CurveGroupTag>& groups = {}, const CgnsRegions* regions = nullptr);

}  // namespace pdmesh
