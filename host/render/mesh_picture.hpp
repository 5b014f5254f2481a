// Pictures of triangle meshes: edges in thin black, boundary edges thicker, optionally each
// triangle filled by a value (a quality measure) with a viridis-like colour bar.
#pragma once
#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "mesh/mesh.hpp"
#include "render/canvas.hpp"

namespace pdmesh {

struct MeshPictureOptions {
  std::string title;
  std::optional<Box> window;                          // default: the mesh's extents + 3%
  const std::vector<double>* triangle_values = nullptr;  // one per triangle; fills and adds a colour bar
  std::string value_label;                            // colour bar caption, e.g. "radius ratio"
  // Values mapped to the two ends of the colour ramp (others clamped); default: the values'
  // finite minimum and maximum. A fixed range makes pictures of different meshes comparable.
  std::optional<std::pair<double, double>> value_range;
  int long_side = 1600;
};

// Viridis-like ramp: t in [0, 1] (clamped) from dark purple through teal to yellow.
Rgb colour_ramp(double t);

// Writes a .png or .svg atomically. Throws Error when triangle_values has the wrong size.
void write_mesh_picture(const std::filesystem::path& path, const Mesh& mesh, const MeshPictureOptions& options);

}  // namespace pdmesh
