// Pictures of triangle meshes: edges in thin black, boundary edges and the interfaces between regions
// thicker, optionally each triangle filled by a value (a quality measure) with a viridis-like colour
// bar, or by its region with a legend.
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
  std::optional<Box> window;                             // default: the mesh's extents + 3%
  const std::vector<double>* triangle_values = nullptr;  // one per triangle; fills and adds a colour bar
  std::string value_label;                               // colour bar caption, e.g. "radius ratio"
  // Values mapped to the two ends of the colour ramp (others clamped); default: the values'
  // finite minimum and maximum. A fixed range makes pictures of different meshes comparable.
  std::optional<std::pair<double, double>> value_range;
  // Each triangle filled by its region (Mesh::region) in a categorical palette, with a legend of the
  // regions' names (render/region_fill.hpp); a mesh without regions is filled grey as "no region".
  // Not with triangle_values.
  bool fill_regions = false;
  int long_side = 1600;
  // Horizontal bands shared out to the cores (PNG only; render_picture): a mesh picture drawn after
  // the cleanup is on the run's critical path. More bands than cores even out a mesh's dense parts.
  int bands = 4;
};

// Viridis-like ramp: t in [0, 1] (clamped) from dark purple through teal to yellow.
Rgb colour_ramp(double t);

// Where a colour bar was drawn (pixels), for its caller's labels.
struct ColourBarBox {
  double x = 0, top = 0, width = 0, height = 0;
};
// Draws the ramp as a framed vertical bar in the canvas' side band, the ramp's top (t = 1) at the top.
ColourBarBox draw_colour_ramp_bar(Canvas& canvas);

// The window a mesh picture shows unless told otherwise: the points' extents, padded (padded_window).
Box default_mesh_window(const Mesh& mesh);

// Writes a .png or .svg atomically. Edges between triangles of different regions (region_interfaces)
// are drawn as thick as the boundary edges. Throws Error when triangle_values or Mesh::region (for
// fill_regions) has the wrong size, or when both fills are asked for.
void write_mesh_picture(const std::filesystem::path& path, const Mesh& mesh, const MeshPictureOptions& options);

// A mesh picture's edges long enough to draw (kMinEdgePixels on `canvas`, in its window), in the
// order and the groups they are stroked in: first the edges shorter than kApartEdgePixels, in the
// mesh's order, one group (StrokeBatch strokes it in its batches); then the longer ones, each stroke taking edges whose
// pixel rows, widened by half a pixel, do not meet, as few strokes as the most of them in one such row (cairo's scan
// converter samples a pixel row once where no polygon edge of a path starts or ends in it, 15 times where one does: see
// mesh_picture.cpp). Every band of a picture draws the same strokes.
struct EdgeStrokes {
  std::vector<std::pair<int, int>> edges;  // point indices, in drawing order
  std::vector<std::size_t> ends;           // the end of each group's edges in `edges`
  std::size_t too_short = 0;               // edges in the window too short to draw
};
inline constexpr double kMinEdgePixels = 2.0;
inline constexpr double kApartEdgePixels = 8.0;
EdgeStrokes plan_edge_strokes(const Canvas& canvas, const Mesh& mesh, const std::vector<std::pair<int, int>>& edges);

// A close-up for a mesh too dense for its picture: when more than half of the triangles' edges would be
// shorter than the smallest edge a picture of `window` at `long_side` pixels draws, the window
// around the triangle with the smallest angle (the lowest index among equals), kCloseUpEdges of
// that triangle's longest edges wide, its centre moved half-way towards the mean of the mesh points
// in it (a triangle on the boundary shows the mesh beside it). nullopt for a mesh whose picture shows
// its edges, one without triangles, or one whose close-up would be wider than kCloseUpLargest of
// the window's longer side (a worst triangle in a graded mesh's coarse far field).
struct CloseUp {
  Box window;
  double min_angle = 0.0;  // the triangle's smallest angle, degrees
};
inline constexpr double kCloseUpEdges = 40.0;
inline constexpr double kCloseUpLargest = 0.25;
std::optional<CloseUp> dense_mesh_close_up(const Mesh& mesh, const Box& window, int long_side);

}  // namespace pdmesh
