// Benchmark: Delaunay triangulation of N seeded uniform random points in the unit square,
// single-threaded. Usage: bench_triangulation [N=1000000] [seed=1] [repeats=3]
//                  bench_triangulation --nodes FILE.nodes [repeats=20]: the constrained mesh of a node
//                  file's nodes (what every convergence check and the final triangulation build),
//                  Delaunay alone beside it.
#include <fmt/format.h>

#include <chrono>
#include <ctime>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "mesh/delaunay.hpp"
#include "mesh/triangulate_nodes.hpp"
#include "nodes/node_file.hpp"

namespace {

template <class F>
std::pair<double, double> best_of(int repeats, const F& f) {
  double best = 1e300, best_cpu = 1e300;
  for (int r = 0; r < repeats; ++r) {
    const auto start = std::chrono::steady_clock::now();
    const std::clock_t cpu_start = std::clock();
    f();
    best_cpu = std::min(best_cpu, static_cast<double>(std::clock() - cpu_start) / CLOCKS_PER_SEC);
    best = std::min(best, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  }
  return {best, best_cpu};
}

int bench_node_file(const std::string& path, int repeats) {
  const pdmesh::NodeFile file = pdmesh::read_node_file(path);
  std::size_t triangles = 0;
  const auto [mesh_s, mesh_cpu] =
      best_of(repeats, [&] { triangles = pdmesh::triangulate(file.nodes, file.curve_names).triangles.size(); });
  const auto [dt_s, dt_cpu] = best_of(repeats, [&] { pdmesh::Triangulation tri(file.nodes.x); });
  fmt::print(
      "{}: {} nodes, {} triangles, best of {}: constrained mesh wall {:.2f} ms (cpu {:.2f} ms), Delaunay alone {:.2f} "
      "ms (cpu {:.2f} ms)\n",
      path, file.nodes.x.size(), triangles, repeats, 1e3 * mesh_s, 1e3 * mesh_cpu, 1e3 * dt_s, 1e3 * dt_cpu);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    if (argc > 2 && std::string(argv[1]) == "--nodes")
      return bench_node_file(argv[2], argc > 3 ? std::stoi(argv[3]) : 20);
    const std::size_t count = argc > 1 ? static_cast<std::size_t>(std::stod(argv[1])) : 1000000;
    const std::uint64_t seed = argc > 2 ? std::stoull(argv[2]) : 1;
    const int repeats = argc > 3 ? std::stoi(argv[3]) : 3;
    std::mt19937_64 rng(seed);
    std::vector<pdmesh::Vec2> points(count);
    for (auto& p : points) {
      p.x = static_cast<double>(rng() >> 11) * 0x1p-53;
      p.y = static_cast<double>(rng() >> 11) * 0x1p-53;
    }
    // Wall time is what users see; CPU time is reported too because on a shared machine the
    // wall time also counts the time other processes held the core.
    double best = 1e300, best_cpu = 1e300;
    std::size_t triangles = 0;
    for (int r = 0; r < repeats; ++r) {
      const auto start = std::chrono::steady_clock::now();
      const std::clock_t cpu_start = std::clock();
      pdmesh::Triangulation tri(points);
      const double cpu = static_cast<double>(std::clock() - cpu_start) / CLOCKS_PER_SEC;
      const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      best_cpu = std::min(best_cpu, cpu);
      triangles = tri.inner_triangles().size();
      best = std::min(best, seconds);
    }
    fmt::print(
        "{} points, {} triangles, best of {}: wall {:.3f} s ({:.3g} points/second), cpu {:.3f} s ({:.3g} "
        "points/second)\n",
        count, triangles, repeats, best, static_cast<double>(count) / best, best_cpu,
        static_cast<double>(count) / best_cpu);
    return 0;
  } catch (const std::exception& e) {
    fmt::print(stderr, "bench_triangulation: {}\n", e.what());
    return 1;
  }
}
