// Hessians by central differences and by least-squares quadratic fits on mesh patches (hessian.hpp).
#include "spacing/hessian.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "core/errors.hpp"

namespace pdmesh {

namespace {

constexpr int kUnknowns = 6;  // c, g_x, g_y, H_xx, H_xy, H_yy
constexpr int kMaxRings = 4;

// Least squares min |A z - b| for A of rows x 6 (row-major) by Householder QR. Returns false when a
// column is dependent on the others (|R_kk| below 1e-10 of the largest column norm): the patch does
// not determine a quadratic.
bool least_squares(std::vector<double>& a, std::vector<double>& b, int rows, std::array<double, kUnknowns>& z) {
  double scale = 0.0;
  for (int j = 0; j < kUnknowns; ++j) {
    double s = 0.0;
    for (int i = 0; i < rows; ++i) s += a[i * kUnknowns + j] * a[i * kUnknowns + j];
    scale = std::max(scale, std::sqrt(s));
  }
  std::array<double, kUnknowns> diag{};
  for (int k = 0; k < kUnknowns; ++k) {
    double s = 0.0;
    for (int i = k; i < rows; ++i) s += a[i * kUnknowns + k] * a[i * kUnknowns + k];
    const double alpha = a[k * kUnknowns + k] > 0.0 ? -std::sqrt(s) : std::sqrt(s);
    if (std::fabs(alpha) <= 1e-10 * scale) return false;
    // v = column k below the diagonal minus alpha e_k; H = I - 2 v vᵀ / vᵀ v.
    a[k * kUnknowns + k] -= alpha;
    double vv = 0.0;
    for (int i = k; i < rows; ++i) vv += a[i * kUnknowns + k] * a[i * kUnknowns + k];
    for (int j = k + 1; j < kUnknowns; ++j) {
      double d = 0.0;
      for (int i = k; i < rows; ++i) d += a[i * kUnknowns + k] * a[i * kUnknowns + j];
      const double f = 2.0 * d / vv;
      for (int i = k; i < rows; ++i) a[i * kUnknowns + j] -= f * a[i * kUnknowns + k];
    }
    double d = 0.0;
    for (int i = k; i < rows; ++i) d += a[i * kUnknowns + k] * b[i];
    const double f = 2.0 * d / vv;
    for (int i = k; i < rows; ++i) b[i] -= f * a[i * kUnknowns + k];
    diag[k] = alpha;
  }
  for (int k = kUnknowns - 1; k >= 0; --k) {
    double s = b[k];
    for (int j = k + 1; j < kUnknowns; ++j) s -= a[k * kUnknowns + j] * z[j];
    z[k] = s / diag[k];
  }
  return true;
}

// Neighbours of each point through the triangles, sorted (CSR).
void build_neighbours(std::size_t n, const std::vector<std::array<int, 3>>& triangles, std::vector<int>& start,
                      std::vector<int>& list) {
  std::vector<std::vector<int>> adj(n);
  for (const auto& t : triangles)
    for (int k = 0; k < 3; ++k) {
      adj[t[k]].push_back(t[(k + 1) % 3]);
      adj[t[k]].push_back(t[(k + 2) % 3]);
    }
  start.assign(n + 1, 0);
  list.clear();
  for (std::size_t i = 0; i < n; ++i) {
    auto& a = adj[i];
    std::sort(a.begin(), a.end());
    a.erase(std::unique(a.begin(), a.end()), a.end());
    list.insert(list.end(), a.begin(), a.end());
    start[i + 1] = static_cast<int>(list.size());
  }
}

}  // namespace

Hessian hessian_by_differences(const std::function<double(Vec2)>& u, Vec2 p, double h) {
  const double c = u(p);
  const double xp = u({p.x + h, p.y}), xm = u({p.x - h, p.y});
  const double yp = u({p.x, p.y + h}), ym = u({p.x, p.y - h});
  const double pp = u({p.x + h, p.y + h}), pm = u({p.x + h, p.y - h});
  const double mp = u({p.x - h, p.y + h}), mm = u({p.x - h, p.y - h});
  const double h2 = h * h;
  return {(xp - 2.0 * c + xm) / h2, (pp - pm - mp + mm) / (4.0 * h2), (yp - 2.0 * c + ym) / h2};
}

std::vector<Hessian> recover_hessians(const std::vector<Vec2>& points, const std::vector<std::array<int, 3>>& triangles,
                                      const std::vector<double>& u, std::string_view what) {
  const std::size_t n = points.size();
  for (std::size_t i = 0; i < n; ++i)
    if (!std::isfinite(u[i]))
      throw InputError(fmt::format("{}: the value at point {} ({}, {}) is {}; it must be a finite number", what, i,
                                   points[i].x, points[i].y, u[i]));
  std::vector<int> start, list;
  build_neighbours(n, triangles, start, list);

  std::vector<Hessian> result(n);
  std::vector<int> patch, mark(n, -1);
  std::vector<double> a, b;
  for (std::size_t v = 0; v < n; ++v) {
    if (start[v] == start[v + 1]) continue;  // in no triangle
    const int vi = static_cast<int>(v);
    patch.assign(1, vi);
    mark[v] = vi;
    std::size_t ring_begin = 0;
    bool solved = false;
    for (int ring = 1; ring <= kMaxRings && !solved; ++ring) {
      const std::size_t ring_end = patch.size();
      for (std::size_t k = ring_begin; k < ring_end; ++k)
        for (int j = start[patch[k]]; j < start[patch[k] + 1]; ++j)
          if (mark[list[j]] != vi) {
            mark[list[j]] = vi;
            patch.push_back(list[j]);
          }
      ring_begin = ring_end;
      if (patch.size() < kUnknowns) continue;
      // Coordinates relative to the vertex, scaled by the patch's radius so that the columns are of
      // one size.
      const Vec2 o = points[v];
      double radius = 0.0;
      for (int q : patch) radius = std::max(radius, dist(o, points[q]));
      const int rows = static_cast<int>(patch.size());
      a.assign(rows * kUnknowns, 0.0);
      b.assign(rows, 0.0);
      for (int r = 0; r < rows; ++r) {
        const double dx = (points[patch[r]].x - o.x) / radius, dy = (points[patch[r]].y - o.y) / radius;
        double* row = &a[r * kUnknowns];
        row[0] = 1.0;
        row[1] = dx;
        row[2] = dy;
        row[3] = 0.5 * dx * dx;
        row[4] = dx * dy;
        row[5] = 0.5 * dy * dy;
        b[r] = u[patch[r]];
      }
      std::array<double, kUnknowns> z{};
      if (!least_squares(a, b, rows, z)) continue;
      const double r2 = radius * radius;
      result[v] = {z[3] / r2, z[4] / r2, z[5] / r2};
      solved = true;
    }
    if (!solved)
      throw InputError(
          fmt::format("{}: no quadratic fits the neighbourhood of point {} ({}, {}) within {} rings of "
                      "triangles (its points are collinear or too few)",
                      what, v, points[v].x, points[v].y, kMaxRings));
  }
  return result;
}

}  // namespace pdmesh
