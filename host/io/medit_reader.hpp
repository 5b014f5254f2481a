// Medit's ASCII .mesh, the format of mmg (mmg2d, mmgpy) and its users: a 2-D .mesh (MeshVersionFormatted,
// Dimension 2, Vertices, Triangles, Quadrilaterals, Edges, Corners and RequiredVertices; the Ridges and
// other Required* lists read over) as a mesh (read_mesh's .mesh), and the same .mesh with
// a .sol whose SolAtVertices block holds one solution of type 3, a symmetric tensor per vertex, in 2-D
// the order m11 m12 m22, as metric data. Indices are 1-based; '#' starts a comment; End ends the file.
// Binary .meshb/.solb are refused. One parser serves both.
// Format: mmgtools.org, "Anisotropic metric prescription"; Dobrzynski, Mmg3d user guide, appendix A.
#pragma once
#include <filesystem>
#include <string>

#include "io/mesh_io_common.hpp"
#include "io/metric_mesh_file.hpp"
#include "mesh/mesh.hpp"

namespace pdmesh {

// The mesh of a .mesh file: its points, triangles (clockwise ones turned) and, per edge reference N,
// a curve named by the comment "# ref N: curve NAME" where the file has one (io/medit_writer.hpp
// writes them), else "refN", the curves in the order of their numbers. Triangle references are the
// regions (Mesh::region: the attribute a of a comment "# ref N: region region_<a>", else N, and
// Mesh::region_names the names other comments give; none when all are 0). With Corners or RequiredVertices the node
// kinds (those Fixed, the edges' other vertices Boundary, the rest Interior), else none. Vertex references are not
// kept. With `cells`, the quadrilaterals too (counter-clockwise), and the cells whose reference a comment
// "# ref N: region NAME" names cells->region are in it (region_found: the file has that comment);
// without `cells` the quadrilaterals are skipped with a note. Throws InputError
// "FILE:LINE: what (got 'TEXT')" on a keyword it does not know, Dimension other than 2, a vertex
// index out of range, a truncated file, and for a .meshb path.
Mesh parse_medit_mesh(const std::string& file_label, std::string content, MeshReadReport& report,
                      SurfaceCells* cells = nullptr);
Mesh read_medit_mesh(const std::filesystem::path& path, MeshReadReport& report, SurfaceCells* cells = nullptr);

// Throws InputError "FILE:LINE: what (got 'TEXT')" on: a binary or unknown extension; a keyword it
// does not know; Dimension other than 2; a count that cannot fit in the file; a vertex index out of
// range; a .sol without SolAtVertices, with more than one solution or a type other than 3 (naming
// it: 1 scalar, 2 vector); a vertex count that differs from the mesh's; a value that is not a finite
// number; a metric that is not SPD (naming the vertex, its coordinates and the three values).
// Clockwise triangles are turned counter-clockwise.
MetricMeshData parse_medit_metric(const std::string& mesh_label, std::string mesh_text, const std::string& sol_label,
                                  std::string sol_text);
MetricMeshData load_medit_metric(const std::filesystem::path& mesh_file, const std::filesystem::path& sol_file);

}  // namespace pdmesh
