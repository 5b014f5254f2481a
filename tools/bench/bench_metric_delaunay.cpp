// Benchmark and measure of the Delaunay triangulation in a metric (mesh/metric_delaunay.hpp): on a
// near-unit mesh of issue 37's linear or polar-1 metric (sizes divided by `refine`, so the point
// count grows as refine²) or on uniform random points, the flips, the time (best of `repeats`,
// single-threaded, wall and CPU) and the UGAWG measures of the result beside those of the isotropic
// Delaunay triangulation of the same points.
// Usage: bench_metric_delaunay linear|polar1|random [refine=1] [repeats=3]
//   random: refine² x 2000 uniform points in the unit square, in the polar-1 metric.
#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <ctime>
#include <random>
#include <string>
#include <vector>

#include "mesh/metric_quality.hpp"
#include "mesh/triangulate_nodes.hpp"
#include "spacing/metric.hpp"

namespace {

using pdmesh::Metric;
using pdmesh::Vec2;

constexpr double kPi = 3.14159265358979323846;

// Issue 37's cases, with every size divided by `refine`.
Metric linear(Vec2 p, double refine) {
  return pdmesh::metric_from_sizes(0.1 / refine, (0.001 + 0.198 * std::fabs(p.y - 0.5)) / refine, 0.0);
}
Metric polar1(Vec2 p, double refine) {
  return pdmesh::metric_from_sizes((0.001 + 0.198 * std::fabs(std::hypot(p.x, p.y) - 0.5)) / refine, 0.1 / refine,
                                   std::atan2(p.y, p.x));
}

// Rows one metric height (√3/2) apart across a size h(s) = (0.001 + 0.198 |s|)/refine that grows
// linearly away from s = 0: the offsets s of the rows, from 0 out to `reach` on one side.
std::vector<double> row_offsets(double refine, double reach) {
  std::vector<double> rows{0.0};
  const double growth = std::exp(0.198 * std::sqrt(3.0) / 2.0 / refine);
  for (double h = 0.001; rows.back() + (growth - 1.0) * h / 0.198 < reach;) {
    rows.push_back(rows.back() + (growth - 1.0) * h / 0.198);
    h *= growth;
  }
  return rows;
}

std::vector<Vec2> linear_points(double refine) {
  std::vector<Vec2> pts;
  const auto rows = row_offsets(refine, 0.5);
  const double hx = 0.1 / refine;
  const int columns = static_cast<int>(std::lround(1.0 / hx));
  for (int side = -1; side <= 1; side += 2)
    for (std::size_t r = side < 0 ? 1 : 0; r < rows.size(); ++r) {
      const bool odd = r % 2 == 1;
      for (int i = 0; i <= columns; ++i) {
        const double x = hx * i + (odd ? 0.5 * hx : 0.0);
        if (x <= 1.0) pts.push_back({x, 0.5 + side * rows[r]});
      }
    }
  return pts;
}

// Rings around the origin at the row offsets from r = 0.5, each with points 0.1/refine apart along
// it (every other ring shifted by half a step), kept inside [0, 1]².
std::vector<Vec2> polar1_points(double refine) {
  std::vector<Vec2> pts;
  const auto rows = row_offsets(refine, std::sqrt(2.0) - 0.5);
  for (std::size_t k = 0; k < rows.size(); ++k) {
    const double r = 0.5 + rows[k];
    const int n = static_cast<int>(std::ceil(0.5 * kPi * r / (0.1 / refine)));
    const double step = 0.5 * kPi / n;
    for (int i = 0; i <= n; ++i) {
      const double t = step * (i + (k % 2 == 1 ? 0.5 : 0.0));
      const Vec2 p{r * std::cos(t), r * std::sin(t)};
      if (t <= 0.5 * kPi && p.x <= 1.0 && p.y <= 1.0) pts.push_back(p);
    }
  }
  return pts;
}

std::string summary(const pdmesh::MetricQualitySummary& q) {
  return fmt::format(
      "{} triangles, {:.1f} % of edges in [1/sqrt2, sqrt2], L {:.3f}..{:.3f}, Q min {:.3f} mean {:.3f}, "
      "{:.2f} % below 0.3",
      q.triangles, q.window_percent, q.length_min, q.length_max, q.q_min, q.q_mean, q.q_below_0_3_percent);
}

}  // namespace

int main(int argc, char** argv) {
  const std::string which = argc > 1 ? argv[1] : "linear";
  const double refine = argc > 2 ? std::stod(argv[2]) : 1.0;
  const int repeats = argc > 3 ? std::stoi(argv[3]) : 3;
  pdmesh::NodeSet nodes;
  std::vector<Vec2> pts;
  if (which == "linear") {
    pts = linear_points(refine);
  } else if (which == "polar1") {
    pts = polar1_points(refine);
  } else if (which == "random") {
    std::mt19937_64 rng(1);
    pts.resize(static_cast<std::size_t>(2000 * refine * refine));
    for (auto& p : pts) p = {static_cast<double>(rng() >> 11) * 0x1p-53, static_cast<double>(rng() >> 11) * 0x1p-53};
  } else {
    fmt::print(stderr, "usage: bench_metric_delaunay linear|polar1|random [refine] [repeats]\n");
    return 2;
  }
  for (Vec2 p : pts) nodes.add(p, 0.0, pdmesh::NodeKind::Interior, -1);
  std::vector<Metric> metrics;
  for (Vec2 p : pts) metrics.push_back(which == "linear" ? linear(p, refine) : polar1(p, refine));

  double best = 1e300, best_cpu = 1e300, iso_best = 1e300, iso_cpu = 1e300;
  pdmesh::Mesh mesh, iso;
  pdmesh::MetricDelaunayStats stats;
  for (int r = 0; r < repeats; ++r) {
    auto start = std::chrono::steady_clock::now();
    std::clock_t cpu = std::clock();
    iso = pdmesh::triangulate(nodes, {});
    iso_cpu = std::min(iso_cpu, static_cast<double>(std::clock() - cpu) / CLOCKS_PER_SEC);
    iso_best = std::min(iso_best, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    start = std::chrono::steady_clock::now();
    cpu = std::clock();
    mesh = pdmesh::triangulate_in_metric(nodes, {}, metrics, {}, &stats);
    best_cpu = std::min(best_cpu, static_cast<double>(std::clock() - cpu) / CLOCKS_PER_SEC);
    best = std::min(best, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  }
  fmt::print(
      "{} (refine {}): {} points; metric Delaunay {:.1f} ms wall ({:.1f} ms cpu; the isotropic triangulation alone "
      "{:.1f} ms wall, {:.1f} ms cpu), "
      "{} flips ({:.2f} per point), {} tests, converged {}\n",
      which, refine, pts.size(), 1e3 * best, 1e3 * best_cpu, 1e3 * iso_best, 1e3 * iso_cpu, stats.flips,
      static_cast<double>(stats.flips) / static_cast<double>(pts.size()), stats.tests, stats.converged ? "yes" : "no");
  if (which == "polar1") {
    // The domain of polar-1 is [0, 1]² minus the disc r < 0.5: the triangles across the disc (the
    // points' convex hull spans it) are not part of the mesh.
    for (pdmesh::Mesh* m : {&mesh, &iso}) {
      std::erase_if(m->triangles, [&](const std::array<int, 3>& t) {
        const Vec2 c = (1.0 / 3.0) * (m->points[t[0]] + m->points[t[1]] + m->points[t[2]]);
        return std::hypot(c.x, c.y) < 0.5;
      });
    }
  }
  fmt::print("  in the metric:  {}\n", summary(pdmesh::metric_quality(mesh, metrics)));
  fmt::print("  isotropic:      {}\n", summary(pdmesh::metric_quality(iso, metrics)));
  return 0;
}
