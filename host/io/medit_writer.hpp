// Medit .mesh (ASCII) writer, the format mmg (mmg2d, mmgpy) reads: MeshVersionFormatted 2 (double
// coordinates), Dimension 2, Vertices, Edges, Triangles, Quadrilaterals, Corners, End; 1-based indices,
// a reference after each record.
#pragma once
#include <string>

#include "core/text_sink.hpp"
#include "io/mixed_mesh.hpp"
#include "mesh/mesh.hpp"

namespace pdmesh {

// Curve c's edges get the reference c + 1, named in a comment "# ref c+1: curve NAME" (every curve,
// also one without edges, so names survive; io/medit_reader.hpp reads them back). A vertex's reference
// is that of the first boundary edge at it, 0 off the boundary; triangles have reference 0. The fixed
// nodes (Mesh::kind) are the Corners, which mmg keeps.
// write_medit appends the file's text to `sink` in pieces; medit_string returns it whole.
void write_medit(const Mesh& mesh, TextSink& sink);
std::string medit_string(const Mesh& mesh);

// A layered run's mesh: the core's cells with reference 0, the boundary layer's with reference 1,
// named in a comment "# ref 1: region boundary_layer"; triangles under Triangles, quadrangles under
// Quadrilaterals, each in mesh order.
void write_mixed_medit(const MixedMesh& mesh, TextSink& sink);
std::string mixed_medit_string(const MixedMesh& mesh);

}  // namespace pdmesh
