// Benchmark: Delaunay triangulation of N seeded uniform random points in the unit square,
// single-threaded. Usage: bench_triangulation [N=1000000] [seed=1] [repeats=3]
#include <fmt/format.h>

#include <chrono>
#include <ctime>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "mesh/delaunay.hpp"

int main(int argc, char** argv) {
  try {
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
    fmt::print("{} points, {} triangles, best of {}: wall {:.3f} s ({:.3g} points/second), cpu {:.3f} s ({:.3g} points/second)\n",
               count, triangles, repeats, best, static_cast<double>(count) / best, best_cpu,
               static_cast<double>(count) / best_cpu);
    return 0;
  } catch (const std::exception& e) {
    fmt::print(stderr, "bench_triangulation: {}\n", e.what());
    return 1;
  }
}
