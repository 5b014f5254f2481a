// A mesh of triangles and quadrilaterals in two regions (the particle core and a boundary layer,
// docs/boundary-layers.md), and its writers: Gmsh MSH 4.1 (triangles type 2, quadrangles type 3),
// VTK XML unstructured grid (VTK_TRIANGLE 5, VTK_QUAD 9), SU2 (5, 9), Medit (io/medit_writer.hpp) and CGNS
// (io/cgns_writer.hpp: TRI_3, QUAD_4). Only the
// boundary-layer runs write it; Mesh (mesh/mesh.hpp) stays the triangle mesh every other stage uses.
#pragma once
#include <array>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "io/mesh_io_common.hpp"
#include "mesh/mesh.hpp"
#include "mesh/periodic_links.hpp"

namespace pdmesh {

struct MixedMesh {
  std::vector<Vec2> points;
  std::vector<std::array<int, 4>> cells;  // counter-clockwise; v[3] = -1 for a triangle
  std::vector<std::uint8_t> layer;        // per cell: 1 in the boundary layer, 0 in the core
  std::vector<BoundaryEdge> boundary_edges;
  std::vector<std::string> curve_names;
  std::vector<PointValues> point_data;  // written as VTU point data (a motion run's node_id); usually none
  // The curves' physical groups kept from the input (Mesh::curve_groups): every writer numbers and
  // names the curves by them (curve_tags) as the triangle meshes' writers do. Empty: curve c is c + 1.
  std::vector<CurveGroupTag> curve_groups;
  // Per cell, when the geometry has regions: the attribute of the region the cell lies in (Mesh::region,
  // 0 outside every region), the layer's cells included; empty without regions. Named by region_names.
  std::vector<double> region;
  std::vector<RegionName> region_names;
  std::size_t quads() const;
};

// The region names: physical group / cell data of the layer cells and of the core's.
inline constexpr const char* kLayerRegion = "boundary_layer";
inline constexpr const char* kCoreRegion = "domain";

// The cells' subdomains as the MSH and Medit writers give them: the core's triangles by region as
// region_surfaces gives them from `first` (one "domain" without regions), then every layer cell in
// kLayerRegion, whatever region it lies in, with the tag first + core.names.size() or the next number
// up that no core surface takes. A file holds one subdomain per cell, and a solver or `pdmesh quality`
// finds the layer by its name.
struct MixedSurfaces {
  RegionSurfaces core;
  long long layer_tag = 0;
  std::vector<int> of_cell;  // index into core.names, or core.names.size() for a layer cell
};
MixedSurfaces mixed_surfaces(const MixedMesh& mesh, long long first);

// Physical groups: dimension 1 as curve_tags gives them (one per curve with tag c + 1 without kept
// groups, else one per group over its curves' entities), the core's surfaces and "boundary_layer"
// (dimension 2, mixed_surfaces from the number of curves + 1: without regions "domain" and
// "boundary_layer" on surface entities 1 and 2). The layer's triangles and quadrangles are separate
// element blocks.
// `periodic` (not null or empty): the $Periodic section after the elements, as msh_writer writes it.
std::string mixed_msh41_string(const MixedMesh& mesh, const std::vector<PeriodicLink>* periodic = nullptr);
// Cell data "boundary_layer" (1 in the layer, 0 in the core) and, with regions, "region" (every cell's
// attribute, the layer's included), the point data when there is some, and the curves, their groups
// and the region names as field data (write_vtu_curves), as a triangle mesh's .vtu holds them.
std::string mixed_vtu_string(const MixedMesh& mesh);
// Core cells first, then the layer's; one marker per curve or kept group, as su2_writer writes them
// (SU2 has no volume markers).
std::string mixed_su2_string(const MixedMesh& mesh);

// The mesh formats (io/mesh_formats.hpp's names) whose files hold quadrilaterals, as write_mixed_mesh
// writes them: msh, vtu, su2, mesh, openfoam, cgns.
const std::vector<std::string>& mixed_mesh_format_names();
bool is_mixed_mesh_format(const std::string& format);

// DIR/STEM.msh, .vtu, .su2, .mesh, .cgns and STEM_openfoam for the formats of `formats` among
// mixed_mesh_format_names(): OpenFOAM's patches of `walls`' curves of type wall and CGNS's BCs of them
// BCWall, one per curve or kept group; with regions the mixed_surfaces as OpenFOAM's cellZones and
// CGNS's regions, else CGNS's regions "domain" and "boundary_layer". Each file is atomic and written
// in pieces (core/text_sink.hpp), its points and cells formatted on the worker threads as the triangle meshes' writers
// do; returns the paths written (the msh file with `periodic`'s $Periodic section). Throws InputError for another
// format (msh22, triangle, fort14, 2dm), before any file is written.
std::vector<std::filesystem::path> write_mixed_mesh(const MixedMesh& mesh, const std::filesystem::path& dir,
                                                    const std::string& stem, const std::vector<std::string>& formats,
                                                    const std::vector<PeriodicLink>* periodic = nullptr,
                                                    const std::vector<std::string>& walls = {});

// The curves, boundary edges and points of `mesh` as a Mesh without cells (for link_periodic_nodes).
Mesh boundary_of(const MixedMesh& mesh);

// The mixed mesh of a file's cells as a reader gives them (read_mesh with SurfaceCells): the points,
// curves, curve groups and triangles of `mesh`, then the quads; `layer` marks the cells of the file's region, or
// every quad where the file does not name the region (cells.region_found false, always for SU2).
MixedMesh mixed_mesh_of(const Mesh& mesh, const SurfaceCells& cells);
// The regions of the file `mesh` was read from (Mesh::region per triangle) on its mixed mesh
// (mixed_mesh_of): the triangles keep their attributes and names, the quads take 0, for a picture
// filled by region (add_layer_regions puts every layer cell in one surface). No regions: unchanged.
void add_file_regions(MixedMesh& mixed, const Mesh& mesh);

// The mesh as triangles (each quad split along its shorter diagonal), for the pictures.
Mesh triangulated(const MixedMesh& mesh);
// Mesh::region and region_names of `triangulated(mesh)`, for a picture filled by region: the MSH
// file's surfaces (mixed_surfaces), the core's regions (without regions attribute 1, kCoreRegion), then
// the layer (kLayerRegion).
void add_layer_regions(const MixedMesh& mesh, Mesh& drawn);

// `mesh` (read_mesh's triangles) with the file's quads `cells` split as `triangulated` splits them,
// appended after its triangles: every cell of a layered mesh, for interpolating data on it. The
// points, triangles, curves and point data of `mesh` are kept as they are.
Mesh with_quads_split(Mesh mesh, const SurfaceCells& cells);

}  // namespace pdmesh
