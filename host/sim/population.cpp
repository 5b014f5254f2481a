// Population control: the event schedule and the application of a plan (population_plan.cpp) to the
// node set and its boundary handler. See population.hpp.
#include "sim/population.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>

#include <fmt/format.h>
#include <tuple>

#include "core/errors.hpp"
#include "sim/boundary_handling.hpp"
#include "sim/population_plan.hpp"
#include "sim/population_profile.hpp"
#include "sim/row_locality.hpp"

namespace pdmesh {

int population_last_event(const PopulationOptions& options, int iterations) {
  if (!options.enabled || options.every <= 0) return 0;
  const int last = static_cast<int>(std::floor(options.stop * static_cast<double>(iterations)));
  return last >= options.start && last >= 1 ? last : 0;
}

bool population_quiet(const PopulationOptions& options, std::size_t changes, std::size_t nodes) {
  return static_cast<double>(changes) <= options.settle * static_cast<double>(nodes);
}

void PopulationSchedule::record(const PopulationOptions& options, int iteration, std::size_t changes,
                                std::size_t nodes) {
  last_event = iteration;
  const int every = std::max(1, options.every);
  if (!population_quiet(options, changes, nodes)) {
    last_change = iteration;
    interval = every;
  } else {
    interval = std::min(2 * (interval > 0 ? interval : every), kPopulationQuietGrowth * every);
  }
  next = iteration + interval;
}

bool PopulationSchedule::finished(const PopulationOptions& options) const {
  if (!(options.settle > 0.0) || last_event == 0) return false;
  // k consecutive quiet events leave the interval at every x 2^k (k <= 3, below the growth cap).
  const int k = std::clamp(options.settle_events, 1, kPopulationMaxSettleEvents);
  return last_change < last_event && interval >= (std::max(1, options.every) << k);
}

bool population_event_due(const PopulationOptions& options, const PopulationSchedule& schedule, int iteration,
                          int iterations) {
  const int last = population_last_event(options, iterations);
  if (last == 0 || iteration > last || iteration <= schedule.last_event || schedule.finished(options)) return false;
  const int next = schedule.next > 0 ? schedule.next : options.start;
  return iteration == last || iteration == next;
}

PopulationThresholds population_thresholds(const PopulationOptions& options, int iteration, int iterations) {
  const int last = population_last_event(options, iterations);
  const double span = static_cast<double>(last - options.start);
  const double t = span > 0.0 ? std::clamp((iteration - options.start) / span, 0.0, 1.0) : 1.0;
  PopulationThresholds out;
  out.insert = options.insert.at(t);
  out.merge = options.merge.at(t);
  out.remove_valence = options.remove_valence;
  out.boundary_split = options.boundary_split;
  out.boundary = options.boundary;
  return out;
}

PopulationStatus population_status(const PopulationOptions& options, const PopulationSchedule& schedule, int iteration,
                                   int iterations) {
  PopulationStatus s;
  const int last = population_last_event(options, iterations);
  s.active = last > 0 && iteration < last && !schedule.finished(options);
  s.settled = !s.active || (schedule.last_event > 0 && schedule.last_change < schedule.last_event);
  return s;
}

PopulationCounts run_population_event(NodeSet& nodes, BoundaryHandler& boundary, const SpacingField& spacing,
                                      const PopulationThresholds& thresholds, std::vector<int>* old_of_new,
                                      const MetricField* metric, std::optional<Triangulation>* kept) {
  const std::size_t n = nodes.size();
  if (old_of_new) {
    old_of_new->resize(n);
    for (std::size_t i = 0; i < n; ++i) (*old_of_new)[i] = static_cast<int>(i);
  }
  PopulationPlan plan;
  try {
    const population_profile::Timer timer("plan");
    plan = metric ? plan_metric_population_event(nodes, boundary.arcs(), boundary.tree(), *metric, thresholds)
                  : plan_population_event(nodes, boundary.arcs(), boundary.tree(), spacing, thresholds, kept);
  } catch (const InputError&) {
    // Coincident (or all collinear) nodes cannot be triangulated; the forces separate coincident
    // nodes, and a later event sees them. GeometryError is an InputError.
    PopulationCounts skipped;
    skipped.skipped = true;
    return skipped;
  }
  const population_profile::Timer timer("apply");
  for (const auto& [node, p] : plan.moves) {
    boundary.move_interior(nodes, node, p);
    nodes.q[static_cast<std::size_t>(node)] = spacing.at(p);
  }
  // Within a curve from the last gap back, so that the earlier gaps keep their positions.
  std::vector<PopulationPlan::BoundaryInsert> inserts = plan.boundary_inserts;
  std::sort(inserts.begin(), inserts.end(),
            [](const auto& a, const auto& b) { return std::tie(a.curve, b.gap) < std::tie(b.curve, a.gap); });
  for (const auto& b : inserts) {
    const int node = boundary.add_boundary(nodes, b.curve, b.gap, b.arc, 0.0);
    nodes.q[static_cast<std::size_t>(node)] = spacing.at(nodes.x[static_cast<std::size_t>(node)]);
  }
  for (const Vec2& p : plan.interior_inserts) boundary.add_interior(nodes, p, spacing.at(p));
  std::vector<char> remove = std::move(plan.remove);
  remove.resize(nodes.size(), 0);
  if (old_of_new) old_of_new->resize(nodes.size(), -1);
  if (plan.counts.removed() > 0) {
    const std::vector<int> kept = boundary.remove_nodes(nodes, remove);
    if (old_of_new) {
      std::vector<int> composed(kept.size());
      for (std::size_t k = 0; k < kept.size(); ++k) composed[k] = (*old_of_new)[static_cast<std::size_t>(kept[k])];
      *old_of_new = std::move(composed);
    }
  }
  return plan.counts;
}

std::optional<PopulationCounts> PopulationTracker::after_iteration(
    const PopulationOptions& options, int iteration, int iterations, NodeSet& nodes, BoundaryHandler& boundary,
    const SpacingField& spacing, std::vector<int>* old_of_new, const MetricField* metric) {
  if (!population_event_due(options, schedule, iteration, iterations)) return std::nullopt;
  const auto start = std::chrono::steady_clock::now();
  triangulation.reset();
  const PopulationCounts counts =
      run_population_event(nodes, boundary, spacing, population_thresholds(options, iteration, iterations), old_of_new,
                           metric, keep_triangulation && !metric ? &triangulation : nullptr);
  seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (counts.changed()) trace_row_locality(fmt::format("after the event after iteration {}", iteration).c_str(), nodes);
  ++events;
  inserted += counts.inserted();
  removed += counts.removed();
  // An event that could not triangulate the nodes saw nothing: with a settle tolerance it does not
  // count towards settling (without one it is quiet).
  const std::size_t changes =
      counts.skipped && options.settle > 0.0 ? nodes.size() + 1 : counts.inserted() + counts.removed();
  schedule.record(options, iteration, changes, nodes.size());
  // PDMESH_POPULATION_TRACE=1: one line per event on stderr (tuning and diagnosis).
  static const bool trace = std::getenv("PDMESH_POPULATION_TRACE") != nullptr;
  if (trace) {
    const PopulationThresholds t = population_thresholds(options, iteration, iterations);
    const char* state = schedule.finished(options)         ? "; settled, no further event"
                        : schedule.last_change < iteration ? "; quiet"
                                                           : "";
    fmt::print(stderr,
               "population event after iteration {}: insert {:.3f} merge {:.3f}: +{} interior +{} boundary, "
               "-{} merged -{} thinned -{} valence -{} boundary{}; {} nodes{}\n",
               iteration, t.insert, t.merge, counts.inserted_interior, counts.inserted_boundary, counts.merged,
               counts.thinned, counts.valence, counts.removed_boundary, counts.skipped ? " (skipped)" : "",
               nodes.size(), state);
  }
  return counts;
}

}  // namespace pdmesh
