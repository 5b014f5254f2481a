// Sections of text several mesh writers share, appended to a TextSink (core/text_sink.hpp) in
// pieces, so that a writer never holds a whole section of a multi-million-node mesh in memory.
#pragma once
#include "core/text_sink.hpp"
#include "mesh/mesh.hpp"

namespace pdmesh {

// One line per point, "PREFIX<i+1> x y 0" with 17-digit coordinates (MSH 2.2 $Nodes, fort.14's
// nodes with depth 0, .2dm's ND cards).
void append_point_lines(TextSink& sink, const Mesh& mesh, const char* prefix);

// The $NodeData section (MSH 2.2 and 4.1 alike) holding mesh.spacing as the view "q"; nothing when
// the mesh has no spacing values.
void append_msh_spacing_node_data(TextSink& sink, const Mesh& mesh);

// One $NodeData view per mesh.point_data array (the same layout as "q": time 0, node tag = point
// index + 1, its components, 17 digits); a '"' or line break in a name becomes '_'. Throws
// InputError for an array of more than 9 components (Gmsh's and the reader's limit) or of the
// wrong length.
void append_msh_point_data(TextSink& sink, const Mesh& mesh);

}  // namespace pdmesh
