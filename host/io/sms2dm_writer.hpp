// SMS 2-D mesh writer (.2dm): triangles (E3T), nodes (ND) and one named node string (NS) per boundary
// curve.
#pragma once
#include <string>

#include "core/text_sink.hpp"
#include "mesh/mesh.hpp"

namespace pdmesh {

// Every triangle has material 1. The node strings are those of io/boundary_strings (the domain on
// their left, a closed curve's first node repeated last), at most ten ids per line, the last id
// negative and followed by the curve's name (blanks made '_').
// write_sms2dm appends the file's text to `sink` in pieces; sms2dm_string returns it whole.
void write_sms2dm(const Mesh& mesh, TextSink& sink);
std::string sms2dm_string(const Mesh& mesh);

}  // namespace pdmesh
