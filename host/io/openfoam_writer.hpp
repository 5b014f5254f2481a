// OpenFOAM polyMesh writer: the 2-D mesh extruded one cell thick in z (a triangle becomes a prism, a
// quadrilateral a hexahedron), as OpenFOAM's solvers take a two-dimensional case, with the front and
// back faces in one patch of type `empty` and one patch per curve.
#pragma once
#include <filesystem>
#include <string>
#include <vector>

#include "io/mixed_mesh.hpp"

namespace pdmesh {

// The directory's files as text, in the order `write_openfoam` writes them.
struct OpenFoamFiles {
  std::string points, faces, owner, neighbour, boundary;
  std::string cell_zones;  // empty without zones
};

// Named sets of cells (OpenFOAM's cellZones: a mesh's regions, for porous zones or a multi-region
// case's splitMeshRegions -cellZones): `names`, and per cell the index of its zone.
struct OpenFoamZones {
  std::vector<std::string> names;
  std::vector<int> of_cell;
};

// The polyMesh of `mesh` between z = 0 and z = thickness. Faces: the internal faces in OpenFOAM's
// upper-triangular order (by owner, then neighbour; owner the lower cell, the normal towards the
// neighbour), then the boundary faces patch by patch with outward normals: one patch per curve, or
// per physical group of curves (`groups`, Mesh::curve_groups), in the order of their tags (curve_tags,
// as the SU2 markers), named as the SU2 markers (blanks as '_'), of type `wall` where `walls` names
// the group or one of its curves and `patch` otherwise; then `frontAndBack` (type `empty`).
// Throws InputError when a cell side on the mesh's border is no curve's boundary edge, or when a
// side is shared by more than two cells.
// With `zones` (not null), cell_zones lists each zone's cells (ascending).
OpenFoamFiles openfoam_files(const MixedMesh& mesh, const std::vector<std::string>& walls,
                             const std::vector<CurveGroupTag>& groups = {}, const OpenFoamZones* zones = nullptr,
                             double thickness = 1.0);

// DIR/STEM_openfoam/constant/polyMesh, where write_openfoam writes.
std::filesystem::path openfoam_polymesh_dir(const std::filesystem::path& dir, const std::string& stem);
// The files write_openfoam may write there: points, faces, owner, neighbour, boundary, cellZones.
const std::vector<std::string>& openfoam_file_names();

// DIR/STEM_openfoam/constant/polyMesh/{points,faces,owner,neighbour,boundary} and, with zones,
// cellZones, each atomically (a solver's case takes the polyMesh directory beside its own system/
// settings); returns their paths.
std::vector<std::filesystem::path> write_openfoam(const MixedMesh& mesh, const std::filesystem::path& dir,
                                                  const std::string& stem, const std::vector<std::string>& walls,
                                                  const std::vector<CurveGroupTag>& groups = {},
                                                  const OpenFoamZones* zones = nullptr);

}  // namespace pdmesh
