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

}  // namespace pdmesh
