// Population control during the run (thesis ch. 7, "Automatic Node Population Control"): every K
// iterations the node set is triangulated and nodes are inserted into vacancies (triangles whose
// circumradius is large against the local spacing), clusters are merged or thinned, low-valence
// interior nodes are deleted, and boundary gaps along each curve are split or closed. The schedule
// and thresholds are pure functions of the iteration, so a run is reproducible and resumable.
// See docs/simulation.md, "Population control".
#pragma once
#include <cstddef>
#include <optional>
#include <vector>

#include "geometry/geometry_tree.hpp"
#include "mesh/delaunay.hpp"
#include "nodes/node_set.hpp"
#include "spacing/spacing_field.hpp"

namespace pdmesh {

class BoundaryHandler;
class MetricField;

// A threshold that moves linearly from `first` (the first event) to `last` (the last event).
struct PopulationRamp {
  double first = 0.0, last = 0.0;
  double at(double t) const { return first + (last - first) * t; }
};

struct PopulationOptions {
  bool enabled = false;  // the library default is the thesis' fixed node count
  // Iterations between events. A quiet event (see settle) doubles the interval to the next one (up
  // to kPopulationQuietGrowth x every), one that changes more resets it to every: a settled run
  // triangulates rarely.
  int every = 50;
  int start = 100;  // the first event comes after this iteration (the start's transient is over)
  // No event after this fraction of the run: the last event is at floor(stop * iterations), and the
  // lattice relaxes undisturbed after it.
  double stop = 0.8;
  // Vacancy: a triangle whose circumradius exceeds insert * q(circumcentre) gets a node there (or at
  // the midpoint of its longest edge), if that point's nearest node is farther than insert * q too.
  PopulationRamp insert{0.75, 0.7};
  // Cluster: two nodes closer than merge * sigma_ij (sigma_ij = (q_i + q_j) / 2) become one.
  PopulationRamp merge{0.6, 0.65};
  // Interior nodes with at most this many Delaunay neighbours are deleted (0: never).
  int remove_valence = 4;
  // Boundary gaps (arc length between consecutive nodes of a curve) longer than boundary_split * sigma
  // get a node at their middle; a node whose gap is shorter than merge * sigma leaves, unless the
  // merged gap would exceed boundary_split * sigma. Critical points never move or leave.
  double boundary_split = 1.5;
  bool boundary = true;
  // Settledness. An event is quiet when it changes (inserts plus removes) at most settle x the node
  // count after it (0: only an event that changes nothing). With settle > 0, after settle_events
  // consecutive quiet events population control is over: no event follows, so the lattice relaxes
  // undisturbed and a stopping rule can start its window. The annealing lattice keeps opening a few
  // vacancies per event for the whole run (30P30N: 1-13 of 14k nodes per event to the last one), so
  // "changes nothing" alone practically never holds before the last event. The default 0 keeps events
  // up to the last one: ending them early cost up to 2 degrees of smallest angle on NACA 0012 and
  // circle_circle (docs/simulation.md, "Population control", "Settling early: measured").
  double settle = 0.0;
  int settle_events = 2;  // 1..kPopulationMaxSettleEvents
};

// The thresholds of one event (population_thresholds gives them for an iteration of a run).
struct PopulationThresholds {
  double insert = 0.75;
  double merge = 0.6;
  int remove_valence = 4;
  double boundary_split = 1.5;
  bool boundary = true;
};

// What one event did.
struct PopulationCounts {
  std::size_t inserted_interior = 0;  // into vacancies
  std::size_t inserted_boundary = 0;  // into long boundary gaps
  std::size_t merged = 0;             // cluster pairs merged into one node (one node removed each)
  std::size_t thinned = 0;            // interior nodes removed next to a boundary node (clusters)
  std::size_t valence = 0;            // low-valence interior nodes removed
  std::size_t removed_boundary = 0;   // boundary nodes removed from short gaps
  std::size_t inserted() const { return inserted_interior + inserted_boundary; }
  std::size_t removed() const { return merged + thinned + valence + removed_boundary; }
  bool changed() const { return inserted() + removed() > 0; }
  bool skipped = false;  // the event could not triangulate the nodes (coincident nodes) and did nothing
};

// The interval after quiet events grows at most to this multiple of PopulationOptions::every.
inline constexpr int kPopulationQuietGrowth = 8;
// The most consecutive quiet events settle_events may ask for: the schedule counts them by its interval
// (every x 2^k after k of them), which stops growing at kPopulationQuietGrowth = 2^3.
inline constexpr int kPopulationMaxSettleEvents = 3;

// Whether an event that changed `changes` nodes, leaving `nodes`, is quiet (PopulationOptions::settle).
bool population_quiet(const PopulationOptions& options, std::size_t changes, std::size_t nodes);

// The iteration of the last event of a run of `iterations` (0: none): floor(stop * iterations), if
// that is at or after start.
int population_last_event(const PopulationOptions& options, int iterations);
// The thresholds of an event after `iteration` (ramped from start to the last event).
PopulationThresholds population_thresholds(const PopulationOptions& options, int iteration, int iterations);

// Runs one event on the node set and the boundary handler that goes with it (positions, kinds,
// curve lists, arc positions, tangents stay consistent). New nodes get q from `spacing` and no
// velocity (the method has none); they enter the next force evaluation. Deterministic: the same
// nodes and thresholds give the same result. Kept nodes keep their order; inserted nodes are
// appended. `old_of_new`, when given, receives the old index of every node after the event (-1 for
// inserted ones).
// With `metric` set (a metric run), the plan measures lengths in the metric
// (plan_metric_population_event, sigma = 1 in metric units); q still comes from `spacing`.
// With `kept` (not with `metric`), the Delaunay triangulation of the nodes before the event goes there
// (plan_population_event); it stays empty when the event is skipped.
PopulationCounts run_population_event(NodeSet& nodes, BoundaryHandler& boundary, const SpacingField& spacing,
                                      const PopulationThresholds& thresholds, std::vector<int>* old_of_new = nullptr,
                                      const MetricField* metric = nullptr,
                                      std::optional<Triangulation>* kept = nullptr);

// The schedule's state between events (a checkpoint stores it): with the options and the run's
// length it says when the next event comes.
struct PopulationSchedule {
  int next = 0;         // the iteration after which the next event runs (0: options.start)
  int interval = 0;     // the current interval (0: options.every)
  int last_event = 0;   // the iteration after which the last event ran (0: none yet)
  int last_change = 0;  // the same for the last event that was not quiet (population_quiet)
  // Records an event after `iteration` that changed `changes` nodes and left `nodes`, and schedules
  // the next: `every` later after one that was not quiet, twice the last interval (at most
  // kPopulationQuietGrowth x every) after a quiet one.
  void record(const PopulationOptions& options, int iteration, std::size_t changes, std::size_t nodes);
  // Whether population control is over before its last event: settle > 0 and the last
  // settle_events events were quiet (the interval has doubled that many times since the last change).
  bool finished(const PopulationOptions& options) const;
};

// Whether an event runs after `iteration`: the scheduled one, and the last one unless the schedule has
// finished (PopulationSchedule::finished).
bool population_event_due(const PopulationOptions& options, const PopulationSchedule& schedule, int iteration,
                          int iterations);

// Where population control stands after `iteration` (for a stopping rule: stop only once the
// population has settled).
struct PopulationStatus {
  bool active = false;  // events are still to come in this run
  bool settled = true;  // off, finished, past its last event, or the last event was quiet
};
PopulationStatus population_status(const PopulationOptions& options, const PopulationSchedule& schedule, int iteration,
                                   int iterations);

// What both simulation drivers keep between events: after each iteration they call after_iteration,
// which runs the event when one is due, counts it and schedules the next.
struct PopulationTracker {
  PopulationSchedule schedule;
  std::size_t inserted = 0, removed = 0;  // this run's events (not a resumed run's earlier part)
  int events = 0;
  double seconds = 0.0;
  // Set before an iteration whose mesh is measured after it: an event after that iteration (not a
  // metric run's) keeps its triangulation of the nodes before it in `triangulation`, from which the
  // measurement starts (measure_mesh). The measurement takes it; an event without one resets it.
  bool keep_triangulation = false;
  std::optional<Triangulation> triangulation;
  // Runs the event due after `iteration` of a run of `iterations`, if one is; see run_population_event.
  std::optional<PopulationCounts> after_iteration(const PopulationOptions& options, int iteration, int iterations,
                                                  NodeSet& nodes, BoundaryHandler& boundary,
                                                  const SpacingField& spacing, std::vector<int>* old_of_new = nullptr,
                                                  const MetricField* metric = nullptr);
};

}  // namespace pdmesh
