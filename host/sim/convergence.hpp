// The convergence stopping rule (simulation.stop = "converged"): the run ends once its mesh has
// stopped improving, with simulation.iterations as the most it may take. Every `check_every`
// iterations the driver triangulates the nodes (measure_mesh) and hands the measurement to the
// monitor with the iteration's history row and whether population control has settled. The rule
// looks at what the mesh needs, its average aspect ratio and its smallest angle: the average |F|
// keeps falling (or stalls) while the mesh is already as good as it gets, so it cannot tell
// (docs/simulation.md, "When a run stops", has the measurements). Both drivers call it the same way,
// so a host run and a double-precision device run stop after the same iteration.
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "mesh/delaunay.hpp"
#include "mesh/mesh.hpp"
#include "nodes/node_set.hpp"
#include "sim/history.hpp"
#include "spacing/metric_field.hpp"

namespace pdmesh {

struct ConvergenceOptions {
  bool enabled = false;   // false: every iteration up to SimOptions::iterations runs (the thesis)
  int check_every = 100;  // iterations between two measurements of the mesh
  int window = 400;       // iterations over which the mesh must not have changed
  // Converged: over the window the average aspect ratio (R / 2r, 1 = equilateral) of the
  // measurements has stayed within aspect_tolerance (max - min), and the smallest angle has not
  // reached a new best by more than angle_tolerance degrees. Calibrated on the thesis cases from
  // both starts (docs/simulation.md, "When a run stops").
  double aspect_tolerance = 5e-4;
  double angle_tolerance = 0.25;
  int min_iterations = 400;  // never stop before this iteration
  // Judged from population control's last change on too: when an event that changed the node set
  // (one that was not quiet, PopulationSchedule::last_change) ran after an iteration inside the window,
  // the window from the first measurement after it (at least check_every iterations long) converges
  // as well. The event's insertions move the mean aspect ratio in a step that is no drift of the
  // settling nodes; the whole window alone would hold the run until the step has left it. A quiet
  // event changes too little to move it, and a window that spans it is judged whole.
  bool from_last_event = false;
};

// Throws InputError naming the first invalid option.
void check_convergence_options(const ConvergenceOptions& options);

// One measurement of the mesh the nodes make after an iteration.
struct MeshSample {
  int iteration = 0;
  double min_angle = 0.0;     // degrees; NaN when the nodes could not be triangulated
  double aspect_ratio = 0.0;  // average over the triangles
};

// The constrained Delaunay mesh of the nodes (mesh/triangulate_nodes), measured. A node set that does
// not triangulate (coincident nodes in mid-run) gives NaN values, which never count as converged.
// `triangles` (optional) receives the triangles measured (left as they were when the nodes do not
// triangulate): a run that stops here has triangulated its final nodes already (measured_mesh).
// The numbers are those of the triangles in canonical_order, each rotated to start at its smallest
// index: they depend on the set of triangles alone. `start` (optional, reset on return) is a Delaunay
// triangulation of a prefix of the nodes' positions (the population event's of the same iteration,
// PopulationTracker::triangulation): the triangles are made from it when triangulate_triangles_from
// can (no triangles are then handed out), else from scratch.
MeshSample measure_mesh(const NodeSet& nodes, int iteration, std::vector<std::array<int, 3>>* triangles = nullptr,
                        std::optional<Triangulation>* start = nullptr);

// The order of `triangles` (indices into it) by their smallest point index, then by the index after it
// counter-clockwise: one order for a set of triangles, however it is laid out. `points`: the number of
// points the indices refer to.
std::vector<std::uint32_t> canonical_order(const std::vector<std::array<int, 3>>& triangles, std::size_t points);

// The Mesh of the nodes whose triangles measure_mesh handed out (its curves named c0, c1, ...):
// triangulate's, made only for the measurement a run stops at.
Mesh measured_mesh(const NodeSet& nodes, std::vector<std::array<int, 3>> triangles);

// A metric run's measurement: the constrained Delaunay mesh in the metric (triangulate_in_metric with
// metric.at(node)), measured in the metric (mesh/metric_quality: the mean-ratio Q, 1 = equilateral in
// the metric), split into the worst 1 % of the triangles by Q (metric_worst_count) and the others,
// so that the rule and its tolerances apply unchanged and a few triangles cannot hold a settled mesh:
// - min_angle is 60 times the mean Q of the worst triangles (60 for a unit mesh, on the scale of the
//   smallest angle): a new best over the window says they still improve. One triangle moves it by
//   its change of Q over the number of worst triangles, where Q_min would be that one triangle's;
// - aspect_ratio is the mean of 1 / Q over the others (1 for a unit mesh, like R / 2r): the bulk,
//   which the mean of 1 / Q watches down to its poorer triangles. A sliver that flips in a layer
//   (Q between 0.02 and 0.5) would move a mean of 1 / Q over all N triangles by about 48 / N at
//   every measurement; among the worst triangles it moves this one by no more than a triangle at
//   their edge does.
// The physical shapes a metric run aims at are far from equilateral, so the isotropic measures never
// settle there. No mesh is handed back (the mesh stage triangulates a metric run's nodes itself).
MeshSample measure_mesh_in_metric(const NodeSet& nodes, int iteration, const MetricField& metric);

// The number of worst triangles whose mean Q measure_mesh_in_metric takes: 1 in kMetricWorstPer of
// `triangles`, rounded up (at least one; none of none).
constexpr std::size_t kMetricWorstPer = 100;
std::size_t metric_worst_count(std::size_t triangles);

class ConvergenceMonitor {
 public:
  // `samples`: a resumed run's earlier measurements (SimState::convergence), so that it stops where
  // the uninterrupted run would.
  explicit ConvergenceMonitor(const ConvergenceOptions& options, std::vector<MeshSample> samples = {});
  // Whether the driver should measure the mesh after `iteration` (enabled, and a check iteration).
  bool due(int iteration) const;
  // After each iteration: true when the run has converged with this row and should stop after it.
  // `sample` is the measurement after this iteration when due() asked for one (else null);
  // `population_settled` false while population control may still change the node set.
  // `last_change`: the iteration after which population control's last event that was not quiet ran
  // (PopulationSchedule::last_change; 0: none), for ConvergenceOptions::from_last_event.
  bool observe(const HistoryRow& row, const MeshSample* sample, bool population_settled = true, int last_change = 0);
  // Whether the measurements so far say the run has converged after `iteration` (the rule observe()
  // applies). A resumed run asks this first: a run that converged in the very iteration it was
  // interrupted after is complete, as the uninterrupted run would have been.
  bool converged_after(int iteration, bool population_settled = true, int last_change = 0) const;
  const std::vector<MeshSample>& samples() const { return samples_; }
  // Whether the measurement after `iteration` is due and not among the samples: a checkpoint written
  // when a stop request ended that measurement. The resumed run takes it (add_sample) first.
  bool missing_sample(int iteration) const {
    return due(iteration) && (samples_.empty() || samples_.back().iteration != iteration);
  }
  void add_sample(const MeshSample& sample) { samples_.push_back(sample); }
  // Why the rule does not say converged after `iteration`, in words for the progress output (a run
  // that ran to its maximum): population control not settled, too early, no window of measurements
  // yet, a measurement that did not triangulate, the aspect ratio's change over the window, or the
  // smallest angle's new best. Empty when it has converged.
  std::string not_converged_reason(int iteration, bool population_settled = true, int last_change = 0) const;

 private:
  // The rule's verdict after `iteration` and, when it is no, why (converged_after, not_converged_reason).
  struct Verdict;
  Verdict judge(int iteration, bool population_settled, int last_change) const;
  // The rule over the measurements from `start` (one of them) to the newest.
  Verdict judge_window(int start) const;
  ConvergenceOptions options_;
  std::vector<MeshSample> samples_;
};

}  // namespace pdmesh
