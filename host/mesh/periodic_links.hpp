// The periodic pairs of a mesh (docs/geometry-input.md, "Periodic curves"): which mesh point on an
// image curve is the transform of which point on its source curve, for the $Periodic section of the
// msh files and the quality report.
#pragma once
#include <array>
#include <string>
#include <vector>

#include "core/vec2.hpp"
#include "geometry/periodic.hpp"
#include "mesh/mesh.hpp"

namespace pdmesh {

// One [[periodic]] table as the run placed it: the source curve's nodes, and at the same index the
// image curve's node that is their transform (both lists in the source curve's order).
struct PeriodicNodes {
  int source_curve = 0, image_curve = 0;  // geometry curve indices (Mesh::curve_names)
  PeriodicTransform transform;
  std::vector<Vec2> source, image;
};

// The pairs of one table in a mesh: point indices (image, source), and the largest distance between
// T(source point) and its image point.
struct PeriodicLink {
  int curve = 0;         // the image curve
  int source_curve = 0;  // the source curve
  std::array<double, 16> affine{};
  std::vector<std::array<int, 2>> nodes;
  double max_mismatch = 0.0;
};

// The links of every table: each node is found among the mesh's points by its exact coordinates.
// Throws SimulationError naming the curve and the node when one is not a mesh point, or when a curve's
// boundary edges hold a node that is not one of its pair nodes (a step moved, removed or added a
// node it had to keep).
std::vector<PeriodicLink> link_periodic_nodes(const Mesh& mesh, const std::vector<PeriodicNodes>& pairs);

}  // namespace pdmesh
