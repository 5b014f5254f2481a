// The metric of a metric run drawn as ellipses: at every mesh point the ellipse {v : vᵀMv = 1/4}
// (half the unit ellipse, so that the ellipses of the ends of an edge of metric length 1 touch),
// over the mesh's edges in grey and its boundary in black. A mesh close to the metric's unit mesh
// shows ellipses that touch their neighbours without overlapping.
#pragma once
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "core/vec2.hpp"
#include "mesh/mesh.hpp"
#include "spacing/metric.hpp"

namespace pdmesh {

struct MetricPictureOptions {
  std::string title;
  std::optional<Box> window;  // default: the mesh's extents + 3%
  int long_side = 1600;
  int bands = 4;  // horizontal bands shared out to the cores (PNG only; render_picture)
};

// Writes a .png or .svg atomically; metrics[i] is the metric at mesh.points[i]. Throws Error when the
// sizes differ.
void write_metric_picture(const std::filesystem::path& path, const Mesh& mesh, const std::vector<Metric>& metrics,
                          const MetricPictureOptions& options);

}  // namespace pdmesh
