// mmg's Medit ASCII pair for metric data (what mesh-adaptation users already have): a 2-D .mesh
// (MeshVersionFormatted, Dimension 2, Vertices, Triangles; Edges, Quadrilaterals, Corners and the
// Required*/Ridges lists are read over) and a .sol whose SolAtVertices block holds one solution of
// type 3, a symmetric tensor per vertex, in 2-D the order m11 m12 m22. Indices are 1-based; '#'
// starts a comment; End ends the file. Binary .meshb/.solb are refused.
// Format: mmgtools.org, "Anisotropic metric prescription"; Dobrzynski, Mmg3d user guide, appendix A.
#pragma once
#include <filesystem>
#include <string>

#include "io/metric_mesh_file.hpp"

namespace pdmesh {

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
