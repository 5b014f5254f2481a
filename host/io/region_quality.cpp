// Quality per region: each region's triangles copied into a mesh of their own and summarised there.
#include "io/region_quality.hpp"

#include <array>
#include <cstddef>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "core/errors.hpp"
#include "io/mesh_io_common.hpp"
#include "mesh/quality_sum.hpp"

namespace pdmesh {
namespace {

// The options that give `s`'s small-angle threshold and histogram bins.
QualityOptions options_of(const QualitySummary& s) {
  QualityOptions o;
  o.small_angle_deg = s.small_angle_deg;
  o.angle_bin_width = s.min_angle_histogram.width;
  o.aspect_bin_width = s.aspect_ratio_histogram.width;
  o.aspect_bins = static_cast<int>(s.aspect_ratio_histogram.counts.size());
  return o;
}

// The mesh of the triangles `triangles` of `mesh` (in that order) and the points they use, numbered
// in the order the triangles first use them. `index` has one entry per point of `mesh`, all -1, and
// is left so. Throws InputError naming a triangle that refers to a point the mesh does not have.
Mesh region_mesh(const Mesh& mesh, const std::vector<std::size_t>& triangles, std::vector<int>& index) {
  Mesh sub;
  sub.triangles.reserve(triangles.size());
  std::vector<int> used;
  for (const std::size_t t : triangles) {
    std::array<int, 3> tri = mesh.triangles[t];
    for (int& v : tri) {
      if (v < 0 || static_cast<std::size_t>(v) >= index.size())
        throw InputError(
            fmt::format("mesh triangle {} refers to point {} but the mesh has {} points", t, v, mesh.points.size()));
      int& k = index[static_cast<std::size_t>(v)];
      if (k < 0) {
        k = static_cast<int>(sub.points.size());
        sub.points.push_back(mesh.points[static_cast<std::size_t>(v)]);
        used.push_back(v);
      }
      v = k;
    }
    sub.triangles.push_back(tri);
  }
  for (const int v : used) index[static_cast<std::size_t>(v)] = -1;
  return sub;
}

}  // namespace

bool has_regions(const Mesh& mesh) {
  if (mesh.triangles.empty() || mesh.region.size() != mesh.triangles.size()) return false;
  if (!mesh.region_names.empty()) return true;
  for (const double a : mesh.region)
    if (a != 0.0) return true;
  return false;
}

void add_region_quality(const Mesh& mesh, QualitySummary& summary, const SpacingBatch& q) {
  summary.regions.clear();
  if (!has_regions(mesh)) return;
  const RegionSurfaces surfaces = region_surfaces(mesh, 1);  // the names and attributes; tags unused
  // The triangles of each region in triangle order, so that a region's sums run in the order the
  // whole mesh's do (a mesh of one region gets the whole mesh's figures bit for bit).
  std::vector<std::vector<std::size_t>> members(surfaces.names.size());
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
    members[static_cast<std::size_t>(surfaces.of_triangle[t])].push_back(t);
  const QualityOptions options = options_of(summary);
  std::vector<int> index(mesh.points.size(), -1);
  for (std::size_t k = 0; k < surfaces.names.size(); ++k) {
    const Mesh sub = region_mesh(mesh, members[k], index);
    RegionQuality r;
    r.attribute = surfaces.attributes[k];
    r.name = surfaces.names[k];
    r.quality = summarize_quality_of(sub, options);
    r.quality.points = sub.points.size();
    if (summary.has_spacing && q) {
      r.quality.has_spacing = true;
      r.quality.spacing = spacing_conformance(sub, q);
    }
    summary.regions.push_back(std::move(r));
  }
}

void add_region_quality(const Mesh& mesh, QualitySummary& summary, const SpacingCallback& q) {
  if (!q) return add_region_quality(mesh, summary, SpacingBatch{});
  add_region_quality(mesh, summary, [&q](const std::vector<Vec2>& p, std::vector<double>& out) {
    out.resize(p.size());
    for (std::size_t k = 0; k < p.size(); ++k) out[k] = q(p[k]);
  });
}

}  // namespace pdmesh
