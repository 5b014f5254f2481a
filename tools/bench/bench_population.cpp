// Benchmark: one population event's plan (sim/population_plan.cpp: the nodes' Delaunay graph and the
// four rules) and the whole event (the plan applied to the node set) on a jittered hexagonal lattice
// filling a 60-degree rhombus, with a share of its nodes left out (vacancies) and as many doubled
// (clusters). Usage: bench_population [m=1000 (about m^2 nodes)] [repeats=5]. Prints the best wall and
// CPU time of each and a digest of the plan (the same digest from two builds: the same plan). With
// PDMESH_POPULATION_PROFILE=1 each event's parts too (sim/population_profile.hpp).
#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <ctime>
#include <random>
#include <string>
#include <vector>

#include "geometry/geometry.hpp"
#include "geometry/geometry_tree.hpp"
#include "init/initial_distribution.hpp"
#include "lattice_rhombus.hpp"
#include "sim/boundary_handling.hpp"
#include "sim/population.hpp"
#include "sim/population_plan.hpp"
#include "sim/population_profile.hpp"
#include "spacing/refine_regions.hpp"

namespace {

using namespace pdmesh;

Vec2 lattice(double i, double j) { return {i + 0.5 * j, std::sqrt(3.0) / 2.0 * j}; }

// FNV-1a over the bytes of the values.
struct Digest {
  std::uint64_t h = 1469598103934665603ull;
  template <class T>
  void add(const T& v) {
    unsigned char bytes[sizeof(T)];
    std::memcpy(bytes, &v, sizeof(T));
    for (unsigned char b : bytes) h = (h ^ b) * 1099511628211ull;
  }
};

}  // namespace

int main(int argc, char** argv) {
  const int m = argc > 1 ? std::stoi(argv[1]) : 1000;
  const int repeats = argc > 2 ? std::stoi(argv[2]) : 5;
  const Geometry geometry = pdmesh_test::lattice_rhombus(m, lattice);
  const GeometryTree tree(geometry);
  const UniformSpacing spacing(1.0);
  NodeSet nodes = make_boundary_nodes(geometry, spacing);
  std::mt19937_64 rng(7);
  const auto u = [&] { return static_cast<double>(rng() >> 11) * 0x1.0p-53; };
  for (int j = 1; j < m; ++j)
    for (int i = 1; i < m; ++i) {
      const double r = u();
      if (r < 0.002) continue;  // a vacancy
      const Vec2 p = lattice(i, j) + Vec2{0.2 * (u() - 0.5), 0.2 * (u() - 0.5)};
      nodes.add(p, 1.0, NodeKind::Interior, -1);
      if (r > 0.998) nodes.add(p + Vec2{0.3 * (u() - 0.5), 0.3 * (u() - 0.5)}, 1.0, NodeKind::Interior, -1);
    }
  PopulationOptions options;
  options.enabled = true;
  const PopulationThresholds thresholds = population_thresholds(options, options.start, 2000);

  const auto timed = [&](const char* what, const auto& body) {
    double best = 1e300, best_cpu = 1e300;
    for (int r = 0; r < repeats; ++r) {
      const auto start = std::chrono::steady_clock::now();
      const std::clock_t cpu_start = std::clock();
      body();
      best_cpu = std::min(best_cpu, static_cast<double>(std::clock() - cpu_start) / CLOCKS_PER_SEC);
      best = std::min(best, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
      population_profile::print(what);
    }
    fmt::print("{}: {} nodes, best of {}: wall {:.1f} ms, cpu {:.1f} ms\n", what, nodes.size(), repeats, 1e3 * best,
               1e3 * best_cpu);
  };

  BoundaryHandler boundary(tree, nodes);
  Digest plan_digest;
  timed("plan", [&] {
    const PopulationPlan plan = plan_population_event(nodes, boundary.arcs(), tree, spacing, thresholds);
    Digest digest;
    for (const Vec2& p : plan.interior_inserts) digest.add(p);
    for (const auto& [node, p] : plan.moves) {
      digest.add(node);
      digest.add(p);
    }
    for (const auto& insert : plan.boundary_inserts) digest.add(insert.arc);
    for (char r : plan.remove) digest.add(r);
    plan_digest = digest;
  });
  Digest event_digest;
  PopulationCounts counts;
  timed("event", [&] {
    NodeSet edited = nodes;
    BoundaryHandler edited_boundary = boundary;
    counts = run_population_event(edited, edited_boundary, spacing, thresholds);
    Digest digest;
    for (const Vec2& p : edited.x) digest.add(p);
    event_digest = digest;
  });
  fmt::print("plan: +{} -{} (merged {}, valence {}), digest {:016x}; event digest {:016x}\n", counts.inserted(),
             counts.removed(), counts.merged, counts.valence, plan_digest.h, event_digest.h);
  return 0;
}
