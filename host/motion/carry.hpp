// Carrying the previous step's nodes along with moving curves (docs/motion.md, "Carrying the nodes"):
// the nodes of the moving curves move rigidly with them, the nodes around them by the same motion
// weighted by w(d) = 1 - smoothstep(d / radius), d their distance to the moving curves, so that the
// mesh follows the body near it and stays where it is beyond the radius. The other curves' nodes do
// not move. The motion is split into sub-steps (1, 2, 4, ...) until no triangle of the previous mesh
// inverts at any sub-step; the weights are measured again at each sub-step's pose.
#pragma once
#include <array>
#include <vector>

#include "geometry/geometry_tree.hpp"
#include "motion/rigid_motion.hpp"
#include "nodes/node_set.hpp"

namespace pdmesh {

struct CarryRequest {
  const NodeSet* nodes = nullptr;                              // the previous step's nodes (pose `from`)
  const std::vector<std::array<int, 3>>* triangles = nullptr;  // its mesh over them, counter-clockwise
  const GeometryTree* tree = nullptr;                          // the geometry at pose `from`
  std::vector<char> moving;                                    // per curve of tree->geometry(): 1 if it moves
  double radius = 1.0;                                         // where the weight reaches 0
  RigidPose from, to;
  int max_halvings = 8;  // at most 2^max_halvings sub-steps
};

struct CarryResult {
  std::vector<Vec2> x;  // the carried positions, one per node
  int substeps = 1;
};

// The blending weight at distance d: 1 at the body, 0 from `radius` on, C1 in between.
double carry_weight(double d, double radius);

// Carries the nodes. Throws SimulationError naming the first triangle that inverts when even
// 2^max_halvings sub-steps fold the mesh.
CarryResult carry_nodes(const CarryRequest& request);

// The nodes of a moving curve (Boundary nodes on it, Fixed nodes whose curve is one): 1, others 0.
std::vector<char> moving_nodes(const NodeSet& nodes, const std::vector<char>& moving_curves);

// The first triangle (index) whose orientation is not positive at positions x; -1 when none.
long first_inverted(const std::vector<std::array<int, 3>>& triangles, const std::vector<Vec2>& x);

}  // namespace pdmesh
