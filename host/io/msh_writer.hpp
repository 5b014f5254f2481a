// Gmsh MSH writers: version 4.1 ASCII (default) and legacy 2.2 ASCII, with one physical line
// group per boundary curve (named after the curve) or per kept physical group (Mesh::curve_groups:
// its tag and name over all its curves), and one physical surface "domain", or with regional
// attributes (Mesh::region) one physical surface per attribute (its name or "region_<attribute>").
#pragma once
#include <string>

#include "core/text_sink.hpp"
#include "mesh/mesh.hpp"
#include "mesh/periodic_links.hpp"

namespace pdmesh {

// Physical tags (io/mesh_io_common.hpp): dimension 1 as curve_tags gives them (curve c -> c + 1 when
// no curve is in a group; curve entity c + 1); dimension 2 as region_surfaces gives them from number
// of curves + 1: "domain" -> number of curves + 1, the j-th attribute in ascending order -> the
// attribute when it is a positive integer, else number of curves + 1 + j or the next free number
// (surface entity j + 1). Node tags are point index + 1.
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
