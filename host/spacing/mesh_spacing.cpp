// MeshSpacing: checking and evaluating a spacing field given on a background triangle mesh (the file
// is read by io/spacing_mesh_file).
#include "spacing/mesh_spacing.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "core/errors.hpp"
#include "core/parallel.hpp"
#include "core/predicates.hpp"

namespace pdmesh {

MeshSpacing::MeshSpacing(MeshFieldData data) : data_(std::move(data)) {
  if (data_.triangles.empty()) {
    throw InputError(
        fmt::format("{}: the mesh has no triangles; a spacing background mesh needs triangle cells", data_.file));
  }
  if (data_.q.size() != data_.points.size()) {
    throw InputError(fmt::format("{}: '{}' has {} values for {} points", data_.file, data_.array, data_.q.size(),
                                 data_.points.size()));
  }
  check_values();
  check_triangles();
  locator_ = std::make_unique<TriangleLocator>(data_.points, data_.triangles, data_.q);
  const EdgeConflict& c = locator_->edge_conflict();
  if (c.first >= 0) {
    auto tri = [&](int t) {
      const auto& v = data_.triangles[static_cast<std::size_t>(t)];
      return fmt::format("({}, {}, {})", point_label(v[0]), point_label(v[1]), point_label(v[2]));
    };
    const auto pa = data_.points[static_cast<std::size_t>(c.a)], pb = data_.points[static_cast<std::size_t>(c.b)];
    const std::string edge =
        fmt::format("{} - {} (({}, {}) - ({}, {}))", point_label(c.a), point_label(c.b), pa.x, pa.y, pb.x, pb.y);
    const std::string what =
        c.same_side ? fmt::format(
                          "the triangles {} and {} lie on the same side of their shared edge {} (an inverted or "
                          "folded triangle, or two overlapping meshes)",
                          tri(c.first), tri(c.second), edge)
                    : fmt::format("the edge {} belongs to more than two triangles, among them {} and {}", edge,
                                  tri(c.first), tri(c.second));
    throw InputError(fmt::format("{}: {}; a spacing background mesh must not overlap itself", data_.file, what));
  }
  check_overlaps();
}

std::string MeshSpacing::point_label(int i) const {
  const auto k = static_cast<std::size_t>(i);
  return k < data_.point_ids.size() ? fmt::format("node {}", data_.point_ids[k]) : fmt::format("point {}", i);
}

// Only the vertices of triangles matter: a bad value at a point no triangle uses is never interpolated.
void MeshSpacing::check_values() const {
  std::vector<std::uint8_t> used(data_.points.size(), 0);
  for (const auto& t : data_.triangles)
    for (int v : t) used[static_cast<std::size_t>(v)] = 1;
  for (std::size_t i = 0; i < data_.points.size(); ++i) {
    if (!used[i]) continue;
    const Vec2 p = data_.points[i];
    const auto label = point_label(static_cast<int>(i));
    if (!data_.given.empty() && !data_.given[i]) {
      throw InputError(fmt::format("{}: '{}' has no value for {} ({}, {}), a vertex of a triangle", data_.array_where,
                                   data_.array, label, p.x, p.y));
    }
    const double q = data_.q[i];
    if (!std::isfinite(q) || q <= 0.0) {
      throw InputError(fmt::format("{}: '{}' is {} at {} ({}, {}); the spacing must be a finite positive number",
                                   data_.array_where, data_.array, q, label, p.x, p.y));
    }
  }
}

void MeshSpacing::check_triangles() const {
  for (const auto& t : data_.triangles) {
    const Vec2 a = data_.points[static_cast<std::size_t>(t[0])];
    const Vec2 b = data_.points[static_cast<std::size_t>(t[1])];
    const Vec2 c = data_.points[static_cast<std::size_t>(t[2])];
    if (orient2d(a, b, c) == 0.0) {
      throw InputError(fmt::format("{}: the triangle ({}, {}, {}) at ({}, {}), ({}, {}), ({}, {}) has zero area",
                                   data_.file, point_label(t[0]), point_label(t[1]), point_label(t[2]), a.x, a.y, b.x,
                                   b.y, c.x, c.y));
    }
  }
}

// Overlaps the edge rule cannot see (triangles that share no edge, e.g. two meshes laid over each
// other): a triangle's centroid strictly inside another triangle. Only centroids that are strictly
// inside their own triangle (exactly) count, so a sliver whose rounded centroid crossed an edge
// cannot raise a false alarm.
void MeshSpacing::check_overlaps() const {
  Located l;
  for (std::size_t t = 0; t < data_.triangles.size(); ++t) {
    const auto& v = data_.triangles[t];
    const Vec2 a = data_.points[static_cast<std::size_t>(v[0])];
    const Vec2 b = data_.points[static_cast<std::size_t>(v[1])];
    const Vec2 c = data_.points[static_cast<std::size_t>(v[2])];
    const Vec2 centroid{(a.x + b.x + c.x) / 3.0, (a.y + b.y + c.y) / 3.0};
    if (!locator_->strictly_inside(locator_->position_of(static_cast<int>(t)), centroid, l)) continue;
    int other = -1;
    locator_->for_each_triangle_near(centroid, [&](int u) {
      if (other < 0 && static_cast<std::size_t>(u) != t &&
          locator_->strictly_inside(locator_->position_of(u), centroid, l)) {
        other = u;
      }
    });
    if (other >= 0) {
      const auto& o = data_.triangles[static_cast<std::size_t>(other)];
      throw InputError(
          fmt::format("{}: the triangles ({}, {}, {}) and ({}, {}, {}) overlap (the centroid ({}, {}) of "
                      "the first lies inside the second); a spacing background mesh must not overlap itself",
                      data_.file, point_label(v[0]), point_label(v[1]), point_label(v[2]), point_label(o[0]),
                      point_label(o[1]), point_label(o[2]), centroid.x, centroid.y));
    }
  }
}

// The value at the nearest point of the nearest boundary edge (clamped to its ends' range).
double MeshSpacing::outside(Vec2 p) const {
  const BoundaryHit hit = locator_->nearest_boundary(p);
  const auto& e = locator_->boundary_edges()[static_cast<std::size_t>(hit.edge)];
  const double qa = data_.q[static_cast<std::size_t>(e[0])];
  const double qb = data_.q[static_cast<std::size_t>(e[1])];
  return std::clamp(qa + hit.t * (qb - qa), std::min(qa, qb), std::max(qa, qb));
}

double MeshSpacing::at(Vec2 p) const {
  const Located l = locator_->locate(p);
  return l.triangle >= 0 ? locator_->interpolate(l) : outside(p);
}

void MeshSpacing::at_many(const std::vector<Vec2>& p, std::vector<double>& q) const {
  q.resize(p.size());
  // Each thread keeps its last triangle as the next point's first guess (its scratch).
  parallel_for_scratch<Located>(
      p.size(),
      [&](Located& l, std::size_t i) {
        // Strictly inside the last triangle: no other triangle holds the point, so at() would pick it
        // too (and compute the same weights).
        if (l.position >= 0 && locator_->strictly_inside(l.position, p[i], l)) {
          q[i] = locator_->interpolate(l);
          return;
        }
        l = locator_->locate(p[i]);
        q[i] = l.triangle >= 0 ? locator_->interpolate(l) : outside(p[i]);
      },
      kPointsPerThread, kMaxThreads);
}

void MeshSpacing::check_covers(const Geometry& geometry) const {
  const double absolute = kMeshCoverTolerance * geometry.extents.diagonal();
  for (const Curve& curve : geometry.curves) {
    for (std::size_t k = 0; k < curve.points.size(); ++k) {
      const Vec2 p = curve.points[k];
      if (locator_->locate(p).triangle >= 0) continue;
      const BoundaryHit hit = locator_->nearest_boundary(p);
      const auto& e = locator_->boundary_edges()[static_cast<std::size_t>(hit.edge)];
      const double edge =
          dist(data_.points[static_cast<std::size_t>(e[0])], data_.points[static_cast<std::size_t>(e[1])]);
      const double allowed = std::max(absolute, kMeshCoverEdgeFraction * edge);
      if (hit.distance <= allowed) continue;
      throw InputError(fmt::format(
          "{}: the background mesh does not cover the domain: point {} ({}, {}) of curve '{}' ({}) lies {:.6g} "
          "outside it (allowed: {:.3g}, the larger of {} x the geometry's diagonal and {} x the nearest boundary "
          "edge of the mesh)",
          data_.file, k, p.x, p.y, curve.name, curve.file, hit.distance, allowed, kMeshCoverTolerance,
          kMeshCoverEdgeFraction));
    }
  }
}

}  // namespace pdmesh
