// ADCIRC / SCHISM grid writer (fort.14, SCHISM's hgrid.gr3): nodes with a depth, triangles, and the
// boundaries as node strings, open (elevation-specified) or land (no normal flow).
#pragma once
#include <string>
#include <vector>

#include "core/text_sink.hpp"
#include "mesh/mesh.hpp"

namespace pdmesh {

// The grid with depth 0 at every node (bathymetry is interpolated onto the grid afterwards). Curves
// named in open_curves are open boundaries (IBTYPEE 0); every other boundary curve is a land
// boundary: IBTYPE 0 on the outer boundary, 1 around an island. Each boundary is one node string per
// curve with the domain on its left; outer-boundary strings come before island strings, and a closed
// curve repeats its first node last (ADCIRC's convention). Embedded constraints are not boundaries.
// write_fort14 appends the file's text to `sink` in pieces; fort14_string returns it whole.
void write_fort14(const Mesh& mesh, const std::vector<std::string>& open_curves, TextSink& sink);
std::string fort14_string(const Mesh& mesh, const std::vector<std::string>& open_curves);

}  // namespace pdmesh
