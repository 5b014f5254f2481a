// front_curves(): the core's boundary from the layer fronts.
#include "layers/front_geometry.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <string>

#include "core/errors.hpp"

namespace pdmesh {

namespace {

// Whether an open chain's end ray lies on the curve that continues the boundary (its column is
// that curve's, not the front's).
bool on_continuing_curve(const LayerRay& ray) { return ray.slide_segment >= 0 && ray.nodes.size() >= 2; }

}  // namespace

LayerFront core_front(const LayerMesh& layers, std::size_t k) {
  LayerFront front = layers.fronts[k];
  if (front.closed) return front;
  const LayerRay& first = layers.rays[static_cast<std::size_t>(layers.chain_ray_begin[k])];
  const LayerRay& last = layers.rays[static_cast<std::size_t>(layers.chain_ray_begin[k + 1] - 1)];
  std::size_t lo = 0, hi = front.nodes.size();
  if (on_continuing_curve(first)) lo = first.nodes.size() - 1;
  if (on_continuing_curve(last)) hi -= last.nodes.size() - 1;
  if (hi < lo + 2) throw Error(fmt::format("boundary layer: the open front of chain {} has no edge", k));
  front.nodes = std::vector<int>(front.nodes.begin() + static_cast<std::ptrdiff_t>(lo),
                                 front.nodes.begin() + static_cast<std::ptrdiff_t>(hi));
  return front;
}

std::vector<RawCurve> front_curves(const Geometry& geometry, const std::vector<int>& wall_curves,
                                   const LayerMesh& layers) {
  std::vector<RawCurve> out;
  std::vector<int> out_of(geometry.curves.size(), -1);  // geometry curve -> its copy in `out`
  for (std::size_t c = 0; c < geometry.curves.size(); ++c) {
    if (std::find(wall_curves.begin(), wall_curves.end(), static_cast<int>(c)) != wall_curves.end()) continue;
    const Curve& curve = geometry.curves[c];
    out_of[c] = static_cast<int>(out.size());
    out.push_back({curve.name, curve.points, curve.file, curve.line, {}, curve.fixed_points});
  }
  // An open chain's end ray that runs along the curve continuing the boundary (slide_segment): the
  // layer's side covers that curve from the wall node up to the ray's top, so the curve starts at
  // the top instead and the front leaves out the column below it. Returns whether it trimmed.
  // An open chain's end ray on the curve that continues the boundary: the layer's side covers that
  // curve from the wall node up to the ray's top, so the curve starts at the top.
  const auto trim = [&](const LayerRay& ray) {
    if (!on_continuing_curve(ray)) return;
    const Segment& s = geometry.segments[static_cast<std::size_t>(ray.slide_segment)];
    const int k = out_of[static_cast<std::size_t>(s.curve)];
    if (k < 0) throw Error(fmt::format("boundary layer: end ray along wall curve '{}'", geometry.curves[s.curve].name));
    std::vector<Vec2>& points = out[static_cast<std::size_t>(k)].points;
    const Vec2 wall = layers.nodes[static_cast<std::size_t>(ray.wall_node)];
    const Vec2 top = layers.nodes[static_cast<std::size_t>(ray.nodes.back())];
    if (points.front() == wall && s.index == 0)
      points.front() = top;
    else if (points.back() == wall && s.index + 2 == static_cast<int>(points.size()))
      points.back() = top;
    else
      throw Error(fmt::format("boundary layer: end ray at ({}, {}) not along an end of curve '{}'", wall.x, wall.y,
                              geometry.curves[s.curve].name));
  };
  for (std::size_t k = 0; k < layers.fronts.size(); ++k) {
    const LayerFront front = core_front(layers, k);
    const LayerRay& first = layers.rays[static_cast<std::size_t>(layers.chain_ray_begin[k])];
    const LayerRay& last = layers.rays[static_cast<std::size_t>(layers.chain_ray_begin[k + 1] - 1)];
    // Its points are the layer cells' top nodes (and an open chain's end columns off the curves that
    // continue it): the core keeps each one as a fixed node.
    RawCurve curve{geometry.curves[first.curve].name + "_front", {}, "boundary layer", 0, {}, true};
    for (const int node : front.nodes) curve.points.push_back(layers.nodes[node]);
    if (front.closed) {
      curve.points.push_back(curve.points.front());
    } else {
      trim(first);
      trim(last);
    }
    out.push_back(std::move(curve));
  }
  return out;
}

}  // namespace pdmesh
