// Gmsh MSH writers: version 4.1 ASCII (default) and legacy 2.2 ASCII, with one physical line
// group per boundary curve (named after the curve) and one physical surface "domain", or with
// regional attributes (Mesh::region) one physical surface "region_<attribute>" per attribute.
#pragma once
#include <string>

#include "core/text_sink.hpp"
#include "mesh/mesh.hpp"

namespace pdmesh {

// Physical tags: curve c -> c + 1; "domain" -> number of curves + 1, or the j-th attribute in ascending
// order -> number of curves + 1 + j (surface entity j + 1). Node tags are point index + 1.
// The write_* forms append the file's text to `sink` in pieces (a bound sink writes it out as it
// goes); the *_string forms return it whole.
void write_msh41(const Mesh& mesh, TextSink& sink);
void write_msh22(const Mesh& mesh, TextSink& sink);
std::string msh41_string(const Mesh& mesh);
std::string msh22_string(const Mesh& mesh);

}  // namespace pdmesh
