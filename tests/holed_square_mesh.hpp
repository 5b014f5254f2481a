// Test helper: the square [0, 8]^2 with the square hole [3, 5]^2 on fine boundary segments, filled
// by the random initial distribution and triangulated: about 22,000 triangles, more than one block
// (16,384) of the cleanup's parallel loops, so that they take several threads.
#pragma once
#include <string>
#include <vector>

#include "geometry/geometry_tree.hpp"
#include "init/initial_distribution.hpp"
#include "mesh/triangulate_nodes.hpp"
#include "spacing/spacing_field.hpp"
#include "geometry_fixtures.hpp"

namespace pdmesh::fixtures {

struct HoledSquareMesh {
  Geometry g = make_geometry({rectangle({0, 0}, {8, 8}, 96, true), rectangle({3, 3}, {5, 5}, 24, false)});
  GeometryTree tree{g};
  BoundarySpacing spacing{tree};
  NodeSet nodes;
  Mesh mesh;
  // `seed`: the random distribution's.
  explicit HoledSquareMesh(unsigned seed) {
    nodes = make_initial_distribution(tree, spacing, {InitMethod::Random, seed, {}, false}).nodes;
    std::vector<std::string> names;
    for (const Curve& c : g.curves) names.push_back(c.name);
    mesh = triangulate(nodes, names);
  }
};

}  // namespace pdmesh::fixtures
