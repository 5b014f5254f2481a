// The host side of a population-control event in the device-resident run (docs/opencl.md,
// "Population control on the device run"): the event itself is the host reference's
// (sim/population.hpp); this maps the device's per-node state onto the edited node set.
#pragma once
#include <cstdint>
#include <optional>
#include <vector>

#include "sim/boundary_handling.hpp"
#include "sim/population.hpp"
#include "spacing/background_field.hpp"

namespace pdmesh::ocl {

// Runs the event due after `iteration` (if any) on `nodes`, which must hold the state read back from
// the device, and `boundary`. On entry `budgets` and `leaves` hold the device's clearance budgets
// and background leaves per node; when the event changed the node set they are replaced by those the
// node arrays go up with: kept nodes that did not move keep theirs, new and merged nodes get no
// budget (the host tests their first move exactly) and the leaf holding them. old_of_new (when set):
// the event's renumbering, new node k was old node old_of_new[k] (< 0: a new node); empty when the
// node set did not change.
std::optional<PopulationCounts> device_population_event(PopulationTracker& tracker, const PopulationOptions& options,
                                                        int iteration, int iterations, NodeSet& nodes,
                                                        BoundaryHandler& boundary, const BackgroundSpacing& background,
                                                        std::vector<double>& budgets, std::vector<std::int32_t>& leaves,
                                                        std::vector<int>* old_of_new = nullptr);

}  // namespace pdmesh::ocl
