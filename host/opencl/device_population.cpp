// Mapping the device's per-node state across a population-control event; see device_population.hpp.
#include "opencl/device_population.hpp"

#include "sim/population_profile.hpp"

namespace pdmesh::ocl {

std::optional<PopulationCounts> device_population_event(PopulationTracker& tracker, const PopulationOptions& options,
                                                        int iteration, int iterations, NodeSet& nodes,
                                                        BoundaryHandler& boundary, const BackgroundSpacing& background,
                                                        std::vector<double>& budgets, std::vector<std::int32_t>& leaves,
                                                        std::vector<int>* old_of_new_out) {
  std::vector<Vec2> before;
  {
    const population_profile::Timer timer("copy before");
    before = nodes.x;
  }
  std::vector<int> old_of_new;
  const auto counts = tracker.after_iteration(options, iteration, iterations, nodes, boundary, background, &old_of_new);
  if (old_of_new_out) old_of_new_out->clear();
  if (!counts || !counts->changed()) return counts;
  if (old_of_new_out) *old_of_new_out = old_of_new;
  const population_profile::Timer timer("map budgets and leaves");
  std::vector<double> new_budgets(nodes.size(), 0.0);
  std::vector<std::int32_t> new_leaves(nodes.size());
  for (std::size_t k = 0; k < nodes.size(); ++k) {
    const int old = old_of_new[k];
    if (old >= 0 && nodes.x[k] == before[static_cast<std::size_t>(old)]) {
      new_budgets[k] = budgets[static_cast<std::size_t>(old)];
      new_leaves[k] = leaves[static_cast<std::size_t>(old)];
    } else {
      double u, v;
      new_leaves[k] = background_locate(background.data(), nodes.x[k], u, v);
    }
  }
  budgets = std::move(new_budgets);
  leaves = std::move(new_leaves);
  return counts;
}

}  // namespace pdmesh::ocl
