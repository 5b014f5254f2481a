// front_curves(): the core's boundary from the layer fronts.
#include "layers/front_geometry.hpp"

#include <fmt/format.h>

#include <algorithm>

#include "core/errors.hpp"

namespace pdmesh {

std::vector<RawCurve> front_curves(const Geometry& geometry, const std::vector<int>& wall_curves,
                                   const LayerMesh& layers) {
  std::vector<RawCurve> out;
  for (std::size_t c = 0; c < geometry.curves.size(); ++c) {
    if (std::find(wall_curves.begin(), wall_curves.end(), static_cast<int>(c)) != wall_curves.end()) continue;
    const Curve& curve = geometry.curves[c];
    out.push_back({curve.name, curve.points, curve.file, curve.line, {}, curve.fixed_points});
  }
  for (std::size_t k = 0; k < layers.fronts.size(); ++k) {
    const LayerFront& front = layers.fronts[k];
    const LayerRay& first = layers.rays[layers.chain_ray_begin[k]];
    const std::string name = geometry.curves[first.curve].name + "_front";
    if (!front.closed)
      throw InputError(
          fmt::format("boundary layer: the wall chain of curve \"{}\" is open; a core boundary from an "
                      "open front is not made yet",
                      geometry.curves[first.curve].name));
    // Its points are the layer cells' top nodes: the core keeps each one as a fixed node.
    RawCurve curve{name, {}, "boundary layer", 0, {}, true};
    for (const int node : front.nodes) curve.points.push_back(layers.nodes[node]);
    curve.points.push_back(curve.points.front());
    out.push_back(std::move(curve));
  }
  return out;
}

}  // namespace pdmesh
