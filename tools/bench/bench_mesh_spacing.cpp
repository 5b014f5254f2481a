// Benchmark: a spacing field given on a background triangle mesh (spacing.field = "mesh"), on two
// Delaunay meshes of N seeded random points in the unit square: "uniform" points, and "graded"
// points whose density goes as 1/r^2 around the centre (triangle sizes over 3.5 decades, like a
// solution-adapted mesh). Reports the build time (checks + point-location structure), the structure's
// size, and the time per point of at() (random order) and at_many() (random order, and the coherent
// row order in which the background quadtree samples), for points inside, at triangle centroids
// (where the nodes are) and outside the mesh; and the time to parse the mesh as an ASCII .vtu.
// All times are processor time of this single-threaded process.
// Usage: bench_mesh_spacing [points=500000] [queries=1000000] [seed=1]
#include <fmt/format.h>

#include <algorithm>
#include <ctime>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "io/vtu_reader.hpp"
#include "io/vtu_writer.hpp"
#include "mesh/delaunay.hpp"
#include "spacing/mesh_spacing.hpp"

using namespace pdmesh;

namespace {

double unit(std::mt19937_64& rng) { return static_cast<double>(rng() >> 11) * 0x1p-53; }

// Processor time, not wall time: on a shared machine the wall time also counts the time other
// processes held the core.
double cpu_seconds() { return static_cast<double>(std::clock()) / CLOCKS_PER_SEC; }

// CPU ns per point of `run` over `n` points, best of 3.
template <class F>
double ns_per_point(std::size_t n, F run) {
  double best = 1e300;
  for (int r = 0; r < 3; ++r) {
    const double start = cpu_seconds();
    run();
    best = std::min(best, cpu_seconds() - start);
  }
  return best * 1e9 / static_cast<double>(n);
}

void bench(const std::string& name, std::vector<Vec2> points, std::size_t queries, std::uint64_t seed) {
  double start = cpu_seconds();
  std::vector<std::array<int, 3>> triangles = delaunay_triangles(points);
  const double delaunay = (cpu_seconds() - start);
  MeshFieldData d;
  d.file = name;
  d.points = points;
  d.triangles = triangles;
  for (const Vec2 p : points) d.q.push_back(0.01 + std::hypot(p.x - 0.5, p.y - 0.5));

  start = cpu_seconds();
  const TriangleLocator locator(d.points, d.triangles);
  const double locator_build = (cpu_seconds() - start);
  start = cpu_seconds();
  const MeshSpacing field(d);
  const double field_build = (cpu_seconds() - start);
  const LocatorStats s = field.locator().stats();

  std::mt19937_64 rng(seed);
  std::vector<Vec2> inside(queries), centroids(queries), outside(queries / 10);
  for (auto& p : inside) p = {unit(rng), unit(rng)};
  for (auto& p : centroids) {
    const auto& t = triangles[static_cast<std::size_t>(rng() % triangles.size())];
    p = (1.0 / 3.0) * (points[static_cast<std::size_t>(t[0])] + points[static_cast<std::size_t>(t[1])] +
                       points[static_cast<std::size_t>(t[2])]);
  }
  for (auto& p : outside) {
    const double a = 2 * M_PI * unit(rng);
    p = {0.5 + 1.5 * std::cos(a), 0.5 + 1.5 * std::sin(a)};
  }
  // Rows of a grid over the square: the order in which a quadtree's cells are sampled.
  std::vector<Vec2> rows;
  const auto side = static_cast<std::size_t>(std::sqrt(static_cast<double>(queries)));
  for (std::size_t j = 0; j < side; ++j)
    for (std::size_t i = 0; i < side; ++i) rows.push_back({(i + 0.5) / side, (j + 0.5) / side});

  double sink = 0;
  const auto at_loop = [&](const std::vector<Vec2>& ps) {
    return ns_per_point(ps.size(), [&] {
      for (const Vec2 p : ps) sink += field.at(p);
    });
  };
  std::vector<double> q;
  const auto many = [&](const std::vector<Vec2>& ps) {
    return ns_per_point(ps.size(), [&] {
      field.at_many(ps, q);
      sink += q[0];
    });
  };
  const double at_inside = at_loop(inside), at_centroids = at_loop(centroids), at_outside = at_loop(outside);
  const double many_inside = many(inside), many_rows = many(rows), at_rows = at_loop(rows);

  Mesh mesh;
  mesh.points = points;
  mesh.triangles = triangles;
  mesh.spacing = d.q;
  const std::string text = vtu_string(mesh);
  start = cpu_seconds();
  MeshReadReport report;
  MeshPointData pd;
  pd.wanted = "q";
  const Mesh back = parse_vtu(name, text, report, &pd);
  const double parse = (cpu_seconds() - start);

  fmt::print("{}: {} points, {} triangles (Delaunay {:.2f} s)\n", name, points.size(), triangles.size(), delaunay);
  fmt::print("  build: TriangleLocator {:.3f} s; MeshSpacing with all checks {:.3f} s\n", locator_build, field_build);
  fmt::print("  structure: {} leaves, depth {}, {:.2f} references per triangle, {} boundary edges, {:.1f} MB\n",
             s.leaves, s.depth, static_cast<double>(s.references) / static_cast<double>(triangles.size()),
             s.boundary_edges, static_cast<double>(s.bytes) / 1e6);
  fmt::print(
      "  at():      {:6.0f} ns/point random inside, {:6.0f} at triangle centroids, {:6.0f} outside, {:6.0f} in rows\n",
      at_inside, at_centroids, at_outside, at_rows);
  fmt::print("  at_many(): {:6.0f} ns/point random inside, {:6.0f} in rows\n", many_inside, many_rows);
  fmt::print("  ASCII .vtu of {:.0f} MB parsed in {:.2f} s ({} points back)   [checksum {:.3g}]\n",
             static_cast<double>(text.size()) / 1e6, parse, back.points.size(), sink);
}

}  // namespace

int main(int argc, char** argv) {
  try {
    const std::size_t count = argc > 1 ? static_cast<std::size_t>(std::stod(argv[1])) : 500000;
    const std::size_t queries = argc > 2 ? static_cast<std::size_t>(std::stod(argv[2])) : 1000000;
    const std::uint64_t seed = argc > 3 ? std::stoull(argv[3]) : 1;
    std::mt19937_64 rng(seed);
    std::vector<Vec2> uniform(count), graded;
    for (auto& p : uniform) p = {unit(rng), unit(rng)};
    // Uniform in log r between 1e-4 and 0.75: density ~ 1/r^2, sizes ~ r.
    while (graded.size() < count) {
      const double r = 1e-4 * std::pow(0.75 / 1e-4, unit(rng)), a = 2 * M_PI * unit(rng);
      const Vec2 p{0.5 + r * std::cos(a), 0.5 + r * std::sin(a)};
      if (p.x >= 0 && p.x <= 1 && p.y >= 0 && p.y <= 1) graded.push_back(p);
    }
    // The square's corners, so that the mesh covers the unit square.
    for (const Vec2 c : {Vec2{0, 0}, Vec2{1, 0}, Vec2{1, 1}, Vec2{0, 1}}) {
      uniform.push_back(c);
      graded.push_back(c);
    }
    bench("uniform", uniform, queries, seed);
    bench("graded", graded, queries, seed);
    return 0;
  } catch (const std::exception& e) {
    fmt::print(stderr, "bench_mesh_spacing: {}\n", e.what());
    return 1;
  }
}
