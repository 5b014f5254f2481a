// The check of the Verlet candidate caches' tests (test_sim_perf_neighbour_cache,
// test_sim_metric_neighbour_cache): a cache's lists and flags equal an exact build's.
#pragma once
#include <catch2/catch.hpp>

#include "sim/step_backend.hpp"

namespace pdmesh_test {

// `exact` (the exact builder) and `cache` at the same stride; lists, counts and flags (but
// pairs_examined, a cost) equal.
template <class Cache, class Exact>
void require_same_lists(const pdmesh::SimParticles& p, double cutoff, Cache& cache, int stride, Exact exact) {
  pdmesh::NeighbourList exact_list, cached;
  exact_list.stride = cached.stride = stride;
  pdmesh::NeighbourFlags ef, cf;
  exact(p, cutoff, exact_list, ef);
  cache.build(p, cutoff, cached, cf);
  REQUIRE(cached.stride == exact_list.stride);
  REQUIRE(cached.count == exact_list.count);
  REQUIRE(cached.index == exact_list.index);
  REQUIRE(cf.overflow == ef.overflow);
  REQUIRE(cf.max_count == ef.max_count);
  REQUIRE(cf.first_invalid == ef.first_invalid);
  REQUIRE(cf.pairs_within == ef.pairs_within);
}

}  // namespace pdmesh_test
