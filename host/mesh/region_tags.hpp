// Regional attributes on the final triangles (Triangle's -A): from the triangle holding each region
// point, a flood fill across the edges that lie on no curve of the geometry, so that a region is the
// subdomain its point lies in when the constraints bounding it are mesh edges.
#pragma once
#include <vector>

#include "geometry/geometry.hpp"
#include "mesh/mesh.hpp"

namespace pdmesh {

// Per triangle: the attribute of the last region (in `regions` order) whose flood reached it, 0 for
// none; empty when there are no regions. An edge blocks the flood when both its ends lie on one
// segment of `geometry` (to 1e-6 of the edge's length). A region point in no triangle (rounding at a
// curved boundary) starts from the triangle with the nearest centroid.
std::vector<double> region_tags(const Mesh& mesh, const std::vector<GeometryRegion>& regions, const Geometry& geometry);

// The names of the regions' attributes (Mesh::region_names): per attribute the first region's name
// that is not empty, ascending by attribute.
std::vector<RegionName> region_names_of(const std::vector<GeometryRegion>& regions);

// The geometry's physical groups (CurveGroup with a tag) on the mesh's curves (Mesh::curve_groups):
// each group's curves found by name in `curve_names`; a group none of whose curves the mesh has is
// left out, and a curve is in the first group that lists it.
std::vector<CurveGroupTag> curve_groups_of(const std::vector<CurveGroup>& groups,
                                           const std::vector<std::string>& curve_names);

}  // namespace pdmesh
