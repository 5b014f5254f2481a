// Particles in a metric on UGAWG's 2-D linear case (issue 37): the unit square with
// h_x = 0.1, h_y = 0.001 + 0.198 |y - 0.5| (spacing/metric_field.hpp's ExpressionMetricField).
//  1. Boundary: the four sides, nodes at equal metric length (each side's metric length, by the
//     midpoint rule on 20000 steps, divided into round(L) pieces), all Fixed.
//  2. Interior: random points (seeded) with density proportional to sqrt(det M) (rejection), as many
//     as a unit mesh of the complexity C = integral sqrt(det M) has inside: V = 2C/sqrt(3) + (B + 2)/2
//     vertices in all by Euler's formula with 4C/sqrt(3) triangles and B boundary vertices.
//  3. Relaxation on the host reference in metric mode (SimParticles::m11, m12, m22): the metric pair
//     force, time step and moves in metric length, the metric neighbour search; an interior node that
//     would leave the square stops halfway to the side instead.
//  4. Two triangulations of the same nodes by today's isotropic Delaunay (mesh/delaunay.hpp), each
//     measured with mesh/metric_quality.hpp (% of edges in [1/sqrt(2), sqrt(2)], Q min and mean,
//     N / (4C/sqrt(3))): "physical", of the positions; "metric coordinates", of the positions mapped by
//     X = x / 0.1, Y = sign(y - 0.5) ln(1 + 0.198 |y - 0.5| / 0.001) / 0.198, which pull this case's
//     metric back to the identity, so that their Delaunay triangulation is the metric one (a stand-in
//     for the anisotropic Delaunay, which this case alone allows).
// --anneal A: interior nodes get random kicks of metric length up to A, shrinking to 0 at half the run.
// --sliding 1: the side nodes but the corners slide along their sides (Boundary kind) instead of staying Fixed.
// Usage: metric_linear [--iterations N] [--dt DT] [--momentum B] [--stability C] [--seed S] [--sliding 1] [--anneal A]
// [--verbose 1]
// (--verbose 1 lists the triangles with Q < 0.75 of the metric-coordinate triangulation.)
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

#include "core/errors.hpp"
#include "mesh/delaunay.hpp"
#include "mesh/metric_quality.hpp"
#include "sim/reference/reference_backend.hpp"
#include "spacing/metric_complexity.hpp"
#include "spacing/metric_field.hpp"

namespace {

using namespace pdmesh;

void add_node(SimParticles& p, Vec2 x, const Metric& m, std::uint8_t kind) {
  p.x.push_back(x.x);
  p.y.push_back(x.y);
  p.q.push_back(reference::largest_size(m.m11, m.m12, m.m22));
  p.kind.push_back(kind);
  p.prev.push_back(-1);
  p.next.push_back(-1);
  p.tx.push_back(0.0);
  p.ty.push_back(0.0);
  p.m11.push_back(m.m11);
  p.m12.push_back(m.m12);
  p.m22.push_back(m.m22);
}

// Nodes from a to b (a included, b not) at equal metric length.
void place_side(SimParticles& p, const MetricField& field, Vec2 a, Vec2 b) {
  const int steps = 20000;
  const Vec2 v = b - a;
  std::vector<double> cumulative(steps + 1, 0.0);
  for (int k = 0; k < steps; ++k) {
    const Vec2 mid = a + v * ((k + 0.5) / steps);
    cumulative[k + 1] = cumulative[k] + field.at(mid).length(v) / steps;
  }
  const int pieces = std::max(1, static_cast<int>(std::lround(cumulative[steps])));
  int k = 0;
  for (int piece = 0; piece < pieces; ++piece) {
    const double target = cumulative[steps] * piece / pieces;
    while (cumulative[k + 1] < target) ++k;
    const double t = (k + (target - cumulative[k]) / (cumulative[k + 1] - cumulative[k])) / steps;
    const Vec2 x = a + v * t;
    add_node(p, x, field.at(x), kSimFixed);
  }
}

double arg(int argc, char** argv, const std::string& name, double fallback) {
  for (int a = 1; a + 1 < argc; ++a)
    if (argv[a] == name) return std::atof(argv[a + 1]);
  return fallback;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    const int iterations = static_cast<int>(arg(argc, argv, "--iterations", 1000));
    const double dt = arg(argc, argv, "--dt", 0.03);
    const double beta = arg(argc, argv, "--momentum", 0.9);
    const double stability = arg(argc, argv, "--stability", 1.0);
    const auto seed = static_cast<std::uint64_t>(arg(argc, argv, "--seed", 1));
    const bool verbose = arg(argc, argv, "--verbose", 0) != 0.0;
    const bool sliding = arg(argc, argv, "--sliding", 0) != 0.0;
    const double anneal = arg(argc, argv, "--anneal", 0.0);
    const auto field = ExpressionMetricField::from_sizes("0.1", "0.001 + 0.198*abs(y-0.5)", "0");
    Box box;
    box.add({0.0, 0.0});
    box.add({1.0, 1.0});
    const double complexity = complexity_on_box(field, box, 400, 4);

    SimParticles p;
    const Vec2 corners[4] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    for (int s = 0; s < 4; ++s) place_side(p, field, corners[s], corners[(s + 1) % 4]);
    const std::size_t boundary = p.size();
    if (sliding) {
      // Nodes inside the sides slide along them (Boundary kind: forces from the previous and next
      // node of the loop, projected on the side); the corners stay Fixed.
      for (std::size_t i = 0; i < boundary; ++i) {
        const bool corner = (p.x[i] == 0.0 || p.x[i] == 1.0) && (p.y[i] == 0.0 || p.y[i] == 1.0);
        if (corner) continue;
        p.kind[i] = kSimBoundary;
        p.prev[i] = static_cast<std::int32_t>((i + boundary - 1) % boundary);
        p.next[i] = static_cast<std::int32_t>((i + 1) % boundary);
        const bool vertical = p.x[i] == 0.0 || p.x[i] == 1.0;
        p.tx[i] = vertical ? 0.0 : 1.0;
        p.ty[i] = vertical ? 1.0 : 0.0;
      }
    }
    const double vertices = 2.0 * complexity / std::sqrt(3.0) + (static_cast<double>(boundary) + 2.0) / 2.0;
    const auto interior = static_cast<std::size_t>(std::lround(vertices)) - boundary;

    double density_max = 0.0;
    for (int i = 0; i <= 200; ++i)
      for (int j = 0; j <= 200; ++j)
        density_max = std::max(density_max, std::sqrt(field.at({i / 200.0, j / 200.0}).det()));
    std::mt19937_64 rng(seed);
    auto uniform = [&rng] { return static_cast<double>(rng() >> 11) * 0x1.0p-53; };
    while (p.size() < boundary + interior) {
      const Vec2 x{uniform(), uniform()};
      const Metric m = field.at(x);
      if (uniform() * density_max <= std::sqrt(m.det())) add_node(p, x, m, kSimInterior);
    }
    fmt::print("linear case: C = {:.3f}, ideal triangles 4C/sqrt(3) = {:.1f}; {} boundary + {} interior nodes\n",
               complexity, 4.0 * complexity / std::sqrt(3.0), boundary, interior);

    auto backend = make_reference_backend();
    NeighbourList list;
    NeighbourFlags flags;
    ForceResult forces;
    MoveResult moves;
    MomentumState carried;
    const ForceParams params{1.5, 15.0, false, stability};
    for (int it = 0; it < iterations; ++it) {
      build_neighbours_growing(*backend, p, params.cutoff, list, flags);
      backend->compute_forces(p, list, params, forces);
      backend->time_step_and_move(p, forces, dt * dt, moves);
      if (beta > 0.0) backend->apply_momentum(p, forces, beta, 0.0, moves, carried);
      const StepSums sums = backend->reduce(p, forces, moves);
      for (std::size_t i = 0; i < p.size(); ++i) {
        if (p.kind[i] == kSimFixed) continue;
        double x = p.x[i] + moves.dx[i], y = p.y[i] + moves.dy[i];
        if (anneal > 0.0 && p.kind[i] == kSimInterior && 2 * it < iterations) {
          // A random kick of metric length up to anneal, shrinking to 0 at half the run.
          const double a = anneal * (1.0 - 2.0 * it / iterations);
          const reference::SizeTensor sz = reference::size_tensor(p.m11[i], p.m12[i], p.m22[i]);
          const double u = a * (2.0 * uniform() - 1.0), v = a * (2.0 * uniform() - 1.0);
          x += sz.a * u + sz.b * v;
          y += sz.b * u + sz.c * v;
        }
        if (x <= 0.0 || x >= 1.0) x = 0.5 * (p.x[i] + (x <= 0.0 ? 0.0 : 1.0));
        if (y <= 0.0 || y >= 1.0) y = 0.5 * (p.y[i] + (y <= 0.0 ? 0.0 : 1.0));
        p.x[i] = x;
        p.y[i] = y;
        const Metric m = field.at({x, y});
        p.m11[i] = m.m11;
        p.m12[i] = m.m12;
        p.m22[i] = m.m22;
        p.q[i] = reference::largest_size(m.m11, m.m12, m.m22);
      }
      if (it % 100 == 0 || it + 1 == iterations)
        fmt::print("iteration {:5d}: mean |F|_M {:.4e}, max |F|_M {:.4e}\n", it,
                   sums.sum_force / static_cast<double>(sums.moving), sums.max_force);
    }

    fmt::print("last neighbour build: {} pairs within the cut-off, {} candidates examined ({:.1f} per pair)\n",
               flags.pairs_within, flags.pairs_examined,
               static_cast<double>(flags.pairs_examined) /
                   static_cast<double>(std::max<std::uint64_t>(1, flags.pairs_within)));
    Mesh mesh;
    std::vector<Metric> metrics;
    std::vector<Vec2> mapped;
    for (std::size_t i = 0; i < p.size(); ++i) {
      mesh.points.push_back({p.x[i], p.y[i]});
      metrics.push_back(field.at(mesh.points.back()));
      const double d = p.y[i] - 0.5;
      mapped.push_back({p.x[i] / 0.1, std::copysign(std::log1p(0.198 * std::fabs(d) / 0.001) / 0.198, d)});
    }
    for (const bool in_metric : {false, true}) {
      mesh.triangles = delaunay_triangles(in_metric ? mapped : mesh.points);
      const MetricQualitySummary q = metric_quality(mesh, metrics, complexity);
      fmt::print("Delaunay of the {}: vertices {}, triangles {}, edges {}\n",
                 in_metric ? "metric coordinates" : "physical positions", q.vertices, q.triangles, q.edges);
      fmt::print("  edges in [1/sqrt2, sqrt2]: {:.2f} %  (L min {:.3f}, max {:.3f})\n", q.window_percent, q.length_min,
                 q.length_max);
      fmt::print("  Q min {:.3f}, Q mean {:.3f}, Q < 0.3: {:.2f} %, N / ideal = {:.3f}\n", q.q_min, q.q_mean,
                 q.q_below_0_3_percent, q.n_over_ideal);
      if (in_metric && verbose) {
        const std::vector<double> qs = metric_qualities(mesh.points, mesh.triangles, metrics);
        for (std::size_t t = 0; t < qs.size(); ++t)
          if (qs[t] < 0.75) {
            const auto& tri = mesh.triangles[t];
            int fixed = 0;
            for (int v : tri) fixed += static_cast<std::size_t>(v) < boundary;
            fmt::print("  Q {:.3f} at ({:.4f}, {:.4f}), {} boundary corners\n", qs[t], mesh.points[tri[0]].x,
                       mesh.points[tri[0]].y, fixed);
          }
      }
    }
    return 0;
  } catch (const Error& e) {
    fmt::print(stderr, "metric_linear: {}\n", e.what());
    return 1;
  }
}
