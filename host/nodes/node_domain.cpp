// Area enclosed by the boundary-node polygons, loop by loop (see node_domain.hpp).
#include "nodes/node_domain.hpp"

#include <cmath>

namespace pdmesh {

double node_domain_area(const NodeSet& nodes, const Geometry& geometry) {
  double area = 0.0;
  for (const Loop& loop : geometry.loops) {
    // Shoelace over the loop's node chain; each curve's chain includes both end nodes, and the
    // repeated joint nodes add zero-length edges, which contribute nothing.
    double twice = 0.0;
    for (std::size_t k = 0; k < loop.curves.size(); ++k) {
      const std::vector<int>& chain = nodes.curve_nodes[static_cast<std::size_t>(loop.curves[k])];
      const bool reversed = loop.reversed[k] != 0;
      for (std::size_t m = 0; m + 1 < chain.size(); ++m) {
        const std::size_t a = reversed ? chain.size() - 1 - m : m;
        const std::size_t b = reversed ? a - 1 : a + 1;
        twice += cross(nodes.x[static_cast<std::size_t>(chain[a])], nodes.x[static_cast<std::size_t>(chain[b])]);
      }
    }
    area += (loop.depth % 2 == 0 ? 1.0 : -1.0) * std::fabs(0.5 * twice);
  }
  return area;
}

}  // namespace pdmesh
