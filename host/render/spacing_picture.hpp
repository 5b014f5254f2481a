// Pictures of the spacing field (`--plot-spacing`, DIR/spacing.png): q as a colour map on a log scale
// over the domain, with a colour bar and the boundary drawn, so a user can see what the field asks for.
#pragma once
#include <filesystem>
#include <optional>
#include <string>

#include "geometry/geometry_tree.hpp"
#include "spacing/background_field.hpp"

namespace pdmesh {

struct SpacingPictureOptions {
  std::string title;          // e.g. "30p30n - spacing field"
  std::optional<Box> window;  // default: the geometry's extents + 3%
  int long_side = 1600;
  // The picture shows value_scale x the field (the field as asked where the nodes relax at a multiple
  // of it, SpacingStage::asked()).
  double value_scale = 1.0;
};

// Samples `field` at every pixel centre inside the domain (outside is white), colours log q with the
// viridis-like ramp, draws the boundary segments in black and a log-scale colour bar. Writes a .png or
// .svg atomically.
void write_spacing_picture(const std::filesystem::path& path, const GeometryTree& tree, const BackgroundSpacing& field,
                           const SpacingPictureOptions& options);

}  // namespace pdmesh
