// The geometry the particle core fills once the layers are made: every curve of the geometry that
// is not a wall, and each closed wall chain replaced by its layer front (docs/boundary-layers.md).
#pragma once
#include <vector>

#include "geometry/geometry.hpp"
#include "layers/boundary_layers.hpp"

namespace pdmesh {

// The curves of the core's geometry, for build_geometry: the non-wall curves of `geometry` as they
// are, then one closed curve "<first wall curve's name>_front" per chain of `layers`. Throws
// InputError for an open chain (its front would have to cut the curves that continue it: not done),
// naming the curves that continue it at its ends, to be added to the wall curves.
std::vector<RawCurve> front_curves(const Geometry& geometry, const std::vector<int>& wall_curves,
                                   const LayerMesh& layers);

}  // namespace pdmesh
