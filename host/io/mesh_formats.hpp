// Mesh file formats by name (writing) and by extension (reading): msh (Gmsh 4.1), msh22
// (Gmsh 2.2), vtu (VTK XML), su2 (SU2 native), triangle (.node/.ele/.poly), fort14 (ADCIRC/SCHISM,
// STEM.14), 2dm (SMS), mesh (Medit, mmg's format), openfoam (an OpenFOAM case directory,
// STEM_openfoam) and cgns (CGNS, HDF5-based; written, not read).
#pragma once
#include <filesystem>
#include <string>
#include <vector>

#include "io/mesh_io_common.hpp"
#include "mesh/mesh.hpp"
#include "mesh/periodic_links.hpp"

namespace pdmesh {

// The format names write_mesh accepts, in documentation order.
const std::vector<std::string>& mesh_format_names();
// True for a name write_mesh accepts.
bool is_mesh_format(const std::string& name);
// The files a format writes, as the extensions that follow the stem: {".msh"} for msh and msh22, {".14"}
// for fort14, {".node", ".ele", ".poly"} for triangle, {"_openfoam"} (a directory) for openfoam. Throws InputError on
// an unknown name.
const std::vector<std::string>& mesh_format_extensions(const std::string& name);
// The files write_mesh may write for a format, relative to its directory: STEM + each extension, or the
// openfoam format's polyMesh files below STEM_openfoam. Throws InputError on an unknown name.
std::vector<std::filesystem::path> mesh_format_files(const std::string& name, const std::string& stem);
// True for a format whose files read_mesh reads back: all but fort14, 2dm, openfoam and cgns.
bool mesh_format_is_read(const std::string& name);

// What some formats need beyond the mesh: the curves that are open boundaries in fort14 (every other
// boundary curve is land).
struct MeshWriteOptions {
  std::vector<std::string> open_boundaries;
  // [[periodic]]: the msh formats write them as $Periodic; the others carry no pairing.
  const std::vector<PeriodicLink>* periodic = nullptr;
  // The msh formats write Mesh::point_data as $NodeData views after "q" (Python's Mesh.write); the
  // commands leave it off, so their .msh files hold the spacing alone.
  bool msh_point_data = false;
  // openfoam and cgns: the curves whose patches are of type wall (the others are of type patch) and
  // whose CGNS boundary conditions are BCWall (the others BCTypeNull).
  std::vector<std::string> walls;
};

// Writes DIR/STEM.msh (msh and msh22 cannot both be asked for: same file), .vtu, .su2, .14, .2dm, .mesh,
// .cgns (io/cgns_writer.hpp), STEM.node/.ele/.poly or the files of STEM_openfoam (io/openfoam_writer.hpp), each
// atomically, and returns the paths written. Throws InputError on an unknown format name (listing the known ones) or an
// unwritable directory.
std::vector<std::filesystem::path> write_mesh(const Mesh& mesh, const std::filesystem::path& dir,
                                              const std::string& stem, const std::vector<std::string>& formats,
                                              const MeshWriteOptions& options = {});

// The files write_mesh or write_mixed_mesh wrote into `dir`, as a progress line names them: each file
// by its name, a directory format's files (openfoam) once, by their directory ("mesh_openfoam/").
std::vector<std::string> written_names(const std::filesystem::path& dir,
                                       const std::vector<std::filesystem::path>& written);

// Reads a mesh by extension: .msh (2.2 or 4.1, from $MeshFormat), .vtu, .su2, .mesh (Medit ASCII; .meshb
// is refused), .ele (with its .node and optional .poly; a .node or .poly path is taken to mean the same
// stem). With `cells`, the quads of an .msh, .vtu, .su2 or .mesh file too, and which cells are in cells->region
// (SurfaceCells, io/mesh_io_common.hpp); Triangle's files hold triangles only. With `data`, the point
// arrays it asks for from an .msh ($NodeData) or .vtu (PointData) file; the other formats carry none.
Mesh read_mesh(const std::filesystem::path& path, MeshReadReport& report, SurfaceCells* cells = nullptr,
               MeshPointData* data = nullptr);
Mesh read_mesh(const std::filesystem::path& path);

}  // namespace pdmesh
