#include "render/metric_picture.hpp"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>

#include "core/errors.hpp"
#include "render/canvas.hpp"

namespace pdmesh {

namespace {

constexpr Rgb kEdgeGrey{0.7, 0.7, 0.7};
constexpr Rgb kEllipse{0.8, 0.1, 0.1};
// An ellipse is drawn as a polygon whose sides stray from it by at most this many pixels.
constexpr double kEllipseTolerancePx = 0.25;
constexpr int kMinEllipseSides = 8;
constexpr int kMaxEllipseSides = 64;

// Sides of a polygon within kEllipseTolerancePx of an ellipse of semi-major axis `radius_px`: a chord
// over the angle 2 pi / n of a circle of radius r strays from it by r (1 - cos(pi / n)) ~ r pi^2 / (2 n^2).
int ellipse_sides(double radius_px) {
  const double n = M_PI * std::sqrt(std::max(radius_px, 0.0) / (2.0 * kEllipseTolerancePx));
  return static_cast<int>(std::clamp(std::ceil(n), double(kMinEllipseSides), double(kMaxEllipseSides)));
}

Box segment_box(Vec2 a, Vec2 b) {
  Box box;
  box.add(a);
  box.add(b);
  return box;
}

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
  // Drawn in bands on several threads (PNG; render_picture): each band strokes the items that reach
  // its rows and skips the others, so that every band flushes its batches after the same items.
  render_picture(
      path, layout,
      [&](Canvas& canvas) {
        {
          StrokeBatch edges(canvas, kEdgeGrey, 0.5);
          for (const auto& t : mesh.triangles) {
            for (int k = 0; k < 3; ++k) {
              const int a = t[k], b = t[(k + 1) % 3];
              if (a >= b) continue;  // an interior edge once (and most boundary ones)
              if (canvas.visible(segment_box(mesh.points[a], mesh.points[b])))
                edges.segment(mesh.points[a], mesh.points[b]);
              else
                edges.skip();
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
          std::vector<Vec2> outline;
          for (std::size_t i = 0; i < mesh.points.size(); ++i) {
            const MetricEigen e = eigen(metrics[i]);
            // Semi-axes 1/(2 sqrt(lambda)): half the sizes h1 (along v1) and h2 (along v2).
            const Vec2 a1 = e.v1() * (0.5 / std::sqrt(e.lambda1));
            const Vec2 a2 = e.v2() * (0.5 / std::sqrt(e.lambda2));
            const Vec2 c = mesh.points[i];
            const Vec2 half{std::hypot(a1.x, a2.x), std::hypot(a1.y, a2.y)};  // the ellipse's bounding box
            if (!canvas.visible(Box{c - half, c + half})) {
              ellipses.skip();
              continue;
            }
            const int sides = ellipse_sides(std::max(norm(a1), norm(a2)) * canvas.scale());
            outline.clear();
            for (int k = 0; k < sides; ++k) {
              const double t = 2.0 * M_PI * k / sides;
              outline.push_back(c + a1 * std::cos(t) + a2 * std::sin(t));
            }
            ellipses.closed_path(outline);
          }
        }
        canvas.title(
            fmt::format("{}   {} points, ellipses of half the metric's sizes", options.title, mesh.points.size()));
      },
      options.bands);
}

}  // namespace pdmesh
