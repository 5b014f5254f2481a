// Pictures of node distributions (thesis figs 4.4-4.13): geometry segments in green, boundary and
// fixed nodes in blue, interior nodes in red, optionally the initialization tree in grey.
#pragma once
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "geometry/geometry.hpp"
#include "nodes/node_set.hpp"

namespace pdmesh {

struct NodePictureOptions {
  std::string title;                             // e.g. "naca0012 - initial"; node counts are appended
  std::optional<Box> window;                     // default: geometry extents + 3%
  const std::vector<Box>* tree_quads = nullptr;  // drawn as thin grey rectangles when set
  int long_side = 1600;
};

// Dot radius in pixels for a node of spacing q drawn at `scale` pixels per unit: proportional to
// q so that zooming in enlarges dots, clamped to [kMinNodeDot, 5] so that dense pictures stay
// readable (a fixed node's dot larger).
inline constexpr double kMinNodeDot = 0.8;
double node_dot_radius(double q, double scale, bool fixed);

// Writes a .png or .svg atomically.
void write_node_picture(const std::filesystem::path& path, const Geometry& geometry, const NodeSet& nodes,
                        const NodePictureOptions& options);

}  // namespace pdmesh
