// SU2 native mesh format (ASCII) writer: triangles are element type 5, boundary edges type 3
// lines in one marker per curve (MARKER_TAG = curve name).
#pragma once
#include <string>

#include "core/text_sink.hpp"
#include "io/mesh_io_common.hpp"
#include "mesh/mesh.hpp"

namespace pdmesh {

// Every curve gets a marker, also one without edges (MARKER_ELEMS= 0), so names survive.
// Blanks in curve names become '_' (a marker tag is one word).
// write_su2 appends the file's text to `sink` in pieces; su2_string returns it whole.
void write_su2(const Mesh& mesh, TextSink& sink);
std::string su2_string(const Mesh& mesh);

}  // namespace pdmesh
