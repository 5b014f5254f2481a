// front_curves(): the core's boundary from the layer fronts.
#include "layers/front_geometry.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <string>

#include "core/errors.hpp"

namespace pdmesh {

namespace {

// The message for an open wall chain (chain k of `layers`): the curves that are not walls and end at
// the chain's end points continue the boundary there; adding them to the wall curves closes it.
std::string open_chain_message(const Geometry& geometry, const std::vector<int>& wall_curves, const LayerMesh& layers,
                               std::size_t k) {
  const LayerRay& first = layers.rays[layers.chain_ray_begin[k]];
  const LayerRay& last = layers.rays[layers.chain_ray_begin[k + 1] - 1];
  std::vector<std::string> names;
  for (const int node : {first.wall_node, last.wall_node}) {
    const Vec2 end = layers.nodes[node];
    for (std::size_t c = 0; c < geometry.curves.size(); ++c) {
      const Curve& curve = geometry.curves[c];
      if (curve.constraint || curve.points.empty() ||
          std::find(wall_curves.begin(), wall_curves.end(), static_cast<int>(c)) != wall_curves.end())
        continue;
      if (curve.points.front() == end || curve.points.back() == end)
        if (std::find(names.begin(), names.end(), curve.name) == names.end()) names.push_back(curve.name);
    }
  }
  std::string message =
      fmt::format("boundary layer: the wall chain of curve \"{}\" is open", geometry.curves[first.curve].name);
  if (names.empty()) return message + "; a core boundary from an open front is not made yet";
  std::string list;
  for (std::size_t i = 0; i < names.size(); ++i)
    list += fmt::format("{}\"{}\"", i == 0 ? "" : (i + 1 == names.size() ? " and " : ", "), names[i]);
  return fmt::format(
      "{}: at its ends the boundary continues along curve{} {}; add {} to boundary_layer.curves so that "
      "the wall curves close their loop (a core boundary from an open front is not made yet)",
      message, names.size() > 1 ? "s" : "", list, names.size() > 1 ? "them" : "it");
}

}  // namespace

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
    if (!front.closed) throw InputError(open_chain_message(geometry, wall_curves, layers, k));
    // Its points are the layer cells' top nodes: the core keeps each one as a fixed node.
    RawCurve curve{name, {}, "boundary layer", 0, {}, true};
    for (const int node : front.nodes) curve.points.push_back(layers.nodes[node]);
    curve.points.push_back(curve.points.front());
    out.push_back(std::move(curve));
  }
  return out;
}

}  // namespace pdmesh
