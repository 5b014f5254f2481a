// Verlet (skin) candidate lists for the metric neighbour search: candidates are gathered with a
// margin and re-filtered exactly on every call, so the lists equal reference::build_neighbours_metric's.
#pragma once
#include <cstdint>
#include <vector>

#include "sim/reference/metric_search.hpp"
#include "sim/step_backend.hpp"

namespace pdmesh::reference {

class MetricNeighbourCache {
 public:
  // skin: each node may move skin * cutoff in its metric at the last rebuild before a rebuild; growth:
  // each node's bubble may grow by this fraction in any direction.
  explicit MetricNeighbourCache(double skin = 0.1, double growth = 0.05);
  // Same contract and results as reference::build_neighbours_metric (p has a metric), except
  // pairs_examined (it counts the candidates re-filtered, plus the nodes a rebuild looked at).
  void build(const SimParticles& p, double cutoff, NeighbourList& list, NeighbourFlags& flags);
  std::uint64_t rebuilds() const { return rebuilds_; }
  // Nodes rebased so far (see metric_neighbour_cache.cpp).
  std::uint64_t rebased() const { return rebased_; }

 private:
  bool same_structure(const SimParticles& p, double cutoff) const;
  // The nodes whose move or growth since their stored state breaks the bound (none: the candidates are
  // complete), at most `limit` + 1 of them.
  std::vector<std::size_t> outgrown(const SimParticles& p, double cutoff, std::size_t limit) const;
  void store_state(const SimParticles& p, std::size_t j);
  bool candidate(std::size_t i, std::size_t j, double bound2) const;
  // The box search over the stored states.
  void index();
  void rebuild(const SimParticles& p, NeighbourFlags& flags);
  void rebase(const SimParticles& p, const std::vector<std::size_t>& nodes, NeighbourFlags& flags);
  double bound2() const;

  double skin_, growth_;
  bool valid_ = false;
  double cutoff_ = 0.0;
  std::uint64_t rebuilds_ = 0, rebased_ = 0;
  // Calls served by the candidates since the last rebuild; calls left to build exactly (after a
  // rebuild that did not pay), and the next such pause.
  int served_ = 0, pause_ = 0, next_pause_ = 1;
  // Each node's state when it was last stored (at a rebuild, or when rebased): position and metric M0
  // (the x, y, m11, m12, m22 of stored_), M0^-1 and M0^(-1/2).
  SimParticles stored_;
  std::vector<double> a11_, a12_, a22_;
  std::vector<SizeTensor> s0_;
  std::vector<std::uint8_t> kind0_;
  // Candidates of interior node i, ascending, i excluded.
  std::vector<std::vector<std::int32_t>> rows_;
  MetricBoxSearch search_;
};

}  // namespace pdmesh::reference
