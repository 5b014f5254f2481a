// The geometry the particle core fills once the layers are made: every curve of the geometry that
// is not a wall, and each wall chain replaced by its layer front (docs/boundary-layers.md).
#pragma once
#include <vector>

#include "geometry/geometry.hpp"
#include "layers/boundary_layers.hpp"

namespace pdmesh {

// The curves of the core's geometry, for build_geometry: the non-wall curves of `geometry`, then one
// curve "<first wall curve's name>_front" per chain of `layers` (closed for a closed chain). An open
// chain's end ray that runs along the curve continuing the boundary (LayerRay::slide_segment) moves
// that curve's end from the wall node to the ray's top, and its front starts there; an end ray off
// the curve leaves the curve as it is and the front runs up that ray from the wall node.
// The nodes of chain k's front that the core's boundary holds: its front, less an open chain's end
// column below the top where that end ray runs along the curve continuing the boundary (that column
// lies on the curve, whose core copy starts at the top).
LayerFront core_front(const LayerMesh& layers, std::size_t k);

std::vector<RawCurve> front_curves(const Geometry& geometry, const std::vector<int>& wall_curves,
                                   const LayerMesh& layers);

}  // namespace pdmesh
