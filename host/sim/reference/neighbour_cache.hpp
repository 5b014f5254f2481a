// Verlet (skin) candidate lists for the reference neighbour search: candidates are gathered with a
// margin and re-filtered exactly on every call, so the lists equal reference::build_neighbours'. Particles
// with a metric go to the metric cache (metric_neighbour_cache.hpp).
#pragma once
#include <cstdint>
#include <vector>

#include "sim/reference/level_grids.hpp"
#include "sim/reference/metric_neighbour_cache.hpp"
#include "sim/step_backend.hpp"

namespace pdmesh::reference {

class NeighbourCache {
 public:
  // skin: each node may move skin * cutoff * q (its spacing at the last rebuild) before a rebuild;
  // growth: each interior node's cut-off radius may grow by this fraction before a rebuild.
  explicit NeighbourCache(double skin = 0.1, double growth = 0.05);
  // Same contract and results as reference::build_neighbours, except pairs_examined (it counts
  // the candidates re-filtered, plus the pairs examined by a rebuild).
  void build(const SimParticles& p, double cutoff, NeighbourList& list, NeighbourFlags& flags);
  std::uint64_t rebuilds() const { return rebuilds_; }
  const MetricNeighbourCache& metric() const { return metric_; }

 private:
  bool same_structure(const SimParticles& p, double cutoff) const;
  bool still_complete(const SimParticles& p, double cutoff) const;
  void rebuild(const SimParticles& p, double cutoff, NeighbourFlags& flags);

  double skin_, growth_;
  bool valid_ = false;
  double cutoff_ = 0.0;
  std::uint64_t rebuilds_ = 0;
  // State at the last rebuild, per node.
  std::vector<double> x0_, y0_;
  std::vector<double> allowed_;     // a_j: allowed displacement
  std::vector<double> allowed2_;    // a_j^2
  std::vector<double> max_radius_;  // Interior nodes: the largest cut-off radius the candidates cover
  std::vector<std::uint8_t> kind0_;
  // Candidates of interior node i: candidates_[first_[i] .. first_[i + 1]), ascending, i excluded.
  std::vector<std::int64_t> first_;
  std::vector<std::int32_t> candidates_;
  // Scratch reused across rebuilds.
  LevelGrids grids_;
  std::vector<double> radius_, level_allowed_, cumulative_allowed_;
  std::vector<std::int32_t> found_;
  MetricNeighbourCache metric_;
};

}  // namespace pdmesh::reference
