// Gmsh MSH writers: version 4.1 ASCII (default) and legacy 2.2 ASCII, with one physical line
// group per boundary curve (named after the curve) and one physical surface "domain", or with
// regional attributes (Mesh::region) one physical surface "region_<attribute>" per attribute.
#pragma once
#include <string>

#include "core/text_sink.hpp"
#include "mesh/mesh.hpp"
#include "mesh/periodic_links.hpp"

namespace pdmesh {

// Physical tags: curve c -> c + 1; "domain" -> number of curves + 1, or the j-th attribute in ascending
// order -> number of curves + 1 + j (surface entity j + 1). Node tags are point index + 1.
// The write_* forms append the file's text to `sink` in pieces (a bound sink writes it out as it
// goes); the *_string forms return it whole.
// `periodic` (when not null or empty) adds the $Periodic section: per link the image curve's entity
// (dim 1, tag curve + 1), the source's, the affine transform's 16 values and the node pairs.
void write_msh41(const Mesh& mesh, TextSink& sink, const std::vector<PeriodicLink>* periodic = nullptr);
void write_msh22(const Mesh& mesh, TextSink& sink, const std::vector<PeriodicLink>* periodic = nullptr);
std::string msh41_string(const Mesh& mesh, const std::vector<PeriodicLink>* periodic = nullptr);
std::string msh22_string(const Mesh& mesh, const std::vector<PeriodicLink>* periodic = nullptr);

// The $Periodic section alone (nothing when `periodic` is null or empty), appended to `out`: MSH 4.1
// gives the affine transform as a count and 16 values, 2.2 on a line "Affine" (the mixed-cell writer
// of a layered run shares it).
void append_msh_periodic(std::string& out, const std::vector<PeriodicLink>* periodic, bool msh41);

}  // namespace pdmesh
