#include "render/metric_picture.hpp"

#include <cmath>
#include <fmt/format.h>

#include "core/errors.hpp"
#include "render/canvas.hpp"

namespace pdmesh {

namespace {

constexpr int kEllipseSegments = 32;
constexpr Rgb kEdgeGrey{0.7, 0.7, 0.7};
constexpr Rgb kEllipse{0.8, 0.1, 0.1};

}  // namespace

void write_metric_picture(const std::filesystem::path& path, const Mesh& mesh, const std::vector<Metric>& metrics,
                          const MetricPictureOptions& options) {
  if (metrics.size() != mesh.points.size()) {
    throw Error(fmt::format("metric picture '{}': {} metrics for {} points", path.string(), metrics.size(),
                            mesh.points.size()));
  }
  Box extents;
  for (const Vec2& p : mesh.points) extents.add(p);
  CanvasOptions layout;
  layout.window = options.window ? *options.window : padded_window(extents);
  layout.long_side = options.long_side;
  render_picture(path, layout, [&](Canvas& canvas) {
    {
      StrokeBatch edges(canvas, kEdgeGrey, 0.5);
      for (const auto& t : mesh.triangles) {
        for (int k = 0; k < 3; ++k) {
          const int a = t[k], b = t[(k + 1) % 3];
          if (a < b) edges.segment(mesh.points[a], mesh.points[b]);  // an interior edge once (and most boundary ones)
        }
      }
    }
    {
      StrokeBatch boundary(canvas, colours::kBlack, 1.5);
      for (const BoundaryEdge& e : mesh.boundary_edges) boundary.segment(mesh.points[e.a], mesh.points[e.b]);
    }
    {
      // Flushed before the title, which would otherwise stroke the batch's last path in its colour.
      StrokeBatch ellipses(canvas, kEllipse, 0.8);
      for (std::size_t i = 0; i < mesh.points.size(); ++i) {
        const MetricEigen e = eigen(metrics[i]);
        // Semi-axes 1/(2 sqrt(lambda)): half the sizes h1 (along v1) and h2 (along v2).
        const Vec2 a1 = e.v1() * (0.5 / std::sqrt(e.lambda1));
        const Vec2 a2 = e.v2() * (0.5 / std::sqrt(e.lambda2));
        const Vec2 c = mesh.points[i];
        Vec2 prev = c + a1;
        for (int k = 1; k <= kEllipseSegments; ++k) {
          const double t = 2.0 * M_PI * k / kEllipseSegments;
          const Vec2 next = c + a1 * std::cos(t) + a2 * std::sin(t);
          ellipses.segment(prev, next);
          prev = next;
        }
      }
    }
    canvas.title(fmt::format("{}   {} points, ellipses of half the metric's sizes", options.title, mesh.points.size()));
  });
}

}  // namespace pdmesh
