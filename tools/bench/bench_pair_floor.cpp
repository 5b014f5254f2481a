// The pair-force floor of the machine it runs on (sim/pair_floor.hpp: the definition), with Google
// Benchmark: one floor iteration (scalar and vector loops), the same bytes streamed alone, and the
// binning, on a settled hexagonal lattice at 14k, 250k, 1M and 5M nodes, threaded over every core.
// Each benchmark is repeated 5 times; "_min" is the best repetition.
//   build/bench_pair_floor                                  every size (5M: ~1 GB, a minute)
//   build/bench_pair_floor --benchmark_filter='/1000000'    one size
// Counters: pair checks per core-second, candidates and pairs within the cut-off per node. `pdmesh
// bench` measures the same floor at each case's node count (measure_pair_floor).
#include <benchmark/benchmark.h>

#include <algorithm>
#include <map>
#include <memory>
#include <thread>

#include "sim/pair_floor.hpp"

namespace {

// One lattice per size, built once (outside the timed loops).
const pdmesh::FloorLattice& lattice(std::size_t nodes) {
  static std::map<std::size_t, std::unique_ptr<pdmesh::FloorLattice>> cache;
  auto& l = cache[nodes];
  if (!l) {
    pdmesh::FloorOptions options;
    options.nodes = nodes;
    l = std::make_unique<pdmesh::FloorLattice>(pdmesh::make_floor_lattice(options));
  }
  return *l;
}

double threads() { return std::max(1u, std::thread::hardware_concurrency()); }

void floor_counters(benchmark::State& state, const pdmesh::FloorLattice& l) {
  const pdmesh::FloorCounts c = pdmesh::count_floor_pairs(l);
  const double n = static_cast<double>(l.size());
  state.counters["checks/core/s"] =
      benchmark::Counter(static_cast<double>(c.candidates) / threads(), benchmark::Counter::kIsIterationInvariantRate);
  state.counters["candidates/node"] = static_cast<double>(c.candidates) / n;
  state.counters["within/node"] = static_cast<double>(c.within) / n;
  state.counters["threads"] = threads();
}

void floor_iteration(benchmark::State& state, pdmesh::FloorLoop loop) {
  const pdmesh::FloorLattice& l = lattice(static_cast<std::size_t>(state.range(0)));
  std::vector<double> new_x, new_y;
  pdmesh::floor_iteration(l, loop, 1e-6, new_x, new_y);  // pages touched before timing
  for (auto _ : state) {
    pdmesh::floor_iteration(l, loop, 1e-6, new_x, new_y);
    benchmark::DoNotOptimize(new_x.data());
    benchmark::ClobberMemory();
  }
  floor_counters(state, l);
  if (loop == pdmesh::FloorLoop::Vector) state.SetLabel(pdmesh::floor_vector_isa());
}

void scalar(benchmark::State& state) { floor_iteration(state, pdmesh::FloorLoop::Scalar); }
void vector(benchmark::State& state) { floor_iteration(state, pdmesh::FloorLoop::Vector); }

// The counting sort of the nodes into the cells, one thread (a run re-bins only when its skin is used up).
void binning(benchmark::State& state) {
  const pdmesh::FloorLattice& l = lattice(static_cast<std::size_t>(state.range(0)));
  pdmesh::FloorLattice sorted;
  sorted.cutoff = l.cutoff;
  for (auto _ : state) {
    pdmesh::bin_floor_points(l.x, l.y, l.q, sorted);
    benchmark::DoNotOptimize(sorted.x.data());
  }
}

double best(const std::vector<double>& v) { return *std::min_element(v.begin(), v.end()); }

void sizes(benchmark::internal::Benchmark* b) {
  for (const long n : {14'000L, 250'000L, 1'000'000L, 5'000'000L, 20'000'000L}) b->Arg(n);
  b->UseRealTime()->Unit(benchmark::kMillisecond)->Repetitions(5)->ComputeStatistics("min", best);
}

}  // namespace

BENCHMARK(scalar)->Apply(sizes);
BENCHMARK(vector)->Apply(sizes);
BENCHMARK(binning)->Apply(sizes);

BENCHMARK_MAIN();
