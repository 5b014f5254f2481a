// The convergence stopping rule; see convergence.hpp.
#include "sim/convergence.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <limits>
#include <string>

#include <fmt/format.h>

#include "core/errors.hpp"
#include "core/interrupt.hpp"
#include "core/parallel.hpp"
#include "mesh/metric_quality.hpp"
#include "mesh/quality.hpp"
#include "mesh/triangulate_nodes.hpp"

namespace pdmesh {

void check_convergence_options(const ConvergenceOptions& o) {
  if (o.check_every < 1) throw InputError(fmt::format("convergence check_every must be >= 1, got {}", o.check_every));
  // The window starts at a measurement: measurements are taken at the multiples of check_every.
  if (o.window < o.check_every || o.window % o.check_every != 0)
    throw InputError(fmt::format("convergence window must be a positive multiple of check_every ({}), got {}",
                                 o.check_every, o.window));
  if (!(o.aspect_tolerance >= 0.0) || !std::isfinite(o.aspect_tolerance))
    throw InputError(fmt::format("convergence aspect tolerance must be >= 0, got {}", o.aspect_tolerance));
  if (!(o.angle_tolerance >= 0.0) || !std::isfinite(o.angle_tolerance))
    throw InputError(fmt::format("convergence angle tolerance must be >= 0, got {}", o.angle_tolerance));
  if (o.min_iterations < 0)
    throw InputError(fmt::format("convergence min_iterations must be >= 0, got {}", o.min_iterations));
}

namespace {

std::vector<std::string> chain_names(const NodeSet& nodes) {
  std::vector<std::string> names(nodes.curve_nodes.size());
  for (std::size_t c = 0; c < names.size(); ++c) names[c] = fmt::format("c{}", c);
  return names;
}

// The corner (0, 1 or 2) of the triangle's smallest point index.
int smallest_corner(const std::array<int, 3>& t) { return t[0] < t[1] ? (t[0] < t[2] ? 0 : 2) : (t[1] < t[2] ? 1 : 2); }

}  // namespace

std::vector<std::uint32_t> canonical_order(const std::vector<std::array<int, 3>>& triangles, std::size_t points) {
  // By the smallest index (a counting sort), then within it by the index after it (counter-clockwise):
  // a directed edge is a side of one triangle at most, so the key is unique.
  const auto first = [](const std::array<int, 3>& t) { return static_cast<std::size_t>(t[smallest_corner(t)]); };
  const auto second = [](const std::array<int, 3>& t) { return t[(smallest_corner(t) + 1) % 3]; };
  std::vector<std::uint32_t> start(points + 1, 0);
  for (const auto& t : triangles) ++start[first(t) + 1];
  for (std::size_t i = 0; i < points; ++i) start[i + 1] += start[i];
  std::vector<std::uint32_t> order(triangles.size());
  for (std::size_t k = 0; k < triangles.size(); ++k)
    order[start[first(triangles[k])]++] = static_cast<std::uint32_t>(k);
  // start[i] is now the end of point i's run (the start of i + 1's).
  for (std::size_t i = 0, lo = 0; i < points; lo = start[i], ++i)
    for (std::size_t a = lo + 1; a < start[i]; ++a)
      for (std::size_t b = a; b > lo && second(triangles[order[b - 1]]) > second(triangles[order[b]]); --b)
        std::swap(order[b - 1], order[b]);
  return order;
}

MeshSample measure_mesh(const NodeSet& nodes, int iteration, std::vector<std::array<int, 3>>* triangles_out,
                        std::optional<Triangulation>* start) {
  constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  MeshSample s{iteration, kNaN, kNaN};
  try {
    // The triangles only: a Mesh (a copy of the points and kinds) is made for the last measurement
    // alone (measured_mesh), and the triangulation's arrays are freed before the shapes are measured.
    const std::vector<std::string> names = chain_names(nodes);
    std::optional<std::vector<std::array<int, 3>>> from_start;
    if (start && *start) {
      from_start = triangulate_triangles_from(std::move(**start), nodes, names);
      start->reset();
    }
    std::vector<std::array<int, 3>> triangles =
        from_start ? std::move(*from_start) : triangulate_triangles(nodes, names);
    if (triangles.empty()) return s;
    // Measured in the canonical order and rotation, so that the same set of triangles gives the same
    // numbers whatever order a triangulation lays them out in. The shapes on every core (the device
    // waits for this check), then the minimum and the sum in that order on this thread: the same bits
    // as one loop. In batches, so that the shapes of a multi-million-triangle mesh are never all held
    // at once.
    const std::vector<std::uint32_t> order = canonical_order(triangles, nodes.size());
    constexpr std::size_t kBatch = std::size_t{1} << 16;
    std::vector<TriangleShape> shapes;
    const std::vector<Vec2>& p = nodes.x;
    double angle = 180.0, aspect = 0.0;
    for (std::size_t first = 0; first < triangles.size(); first += kBatch) {
      shapes.resize(std::min(kBatch, triangles.size() - first));
      parallel_for(shapes.size(), [&](std::size_t b) {
        const auto& t = triangles[order[first + b]];
        const int k = smallest_corner(t);
        shapes[b] = triangle_shape(p[t[k]], p[t[(k + 1) % 3]], p[t[(k + 2) % 3]]);
      });
      for (const TriangleShape& q : shapes) {
        angle = std::min(angle, q.min_angle);
        aspect += q.aspect_ratio;
      }
    }
    s.min_angle = angle;
    s.aspect_ratio = aspect / static_cast<double>(triangles.size());
    // The triangles made from `start` are not triangulate_triangles' order: none handed out (a run that
    // stops here triangulates its nodes again in the mesh stage).
    if (triangles_out && !from_start) *triangles_out = std::move(triangles);
  } catch (const Interrupted&) {
    throw;  // a stop request, not a measurement
  } catch (const Error&) {
    // Nodes that do not triangulate in mid-run (two coincident ones) are simply not converged.
  }
  return s;
}

Mesh measured_mesh(const NodeSet& nodes, std::vector<std::array<int, 3>> triangles) {
  return mesh_of_triangles(nodes, chain_names(nodes), std::move(triangles));
}

std::size_t metric_worst_count(std::size_t triangles) {
  if (triangles == 0) return 0;
  return std::max<std::size_t>(1, (triangles + kMetricWorstPer - 1) / kMetricWorstPer);
}

MeshSample measure_mesh_in_metric(const NodeSet& nodes, int iteration, const MetricField& metric) {
  constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  MeshSample s{iteration, kNaN, kNaN};
  const std::vector<std::string> names = chain_names(nodes);
  try {
    // One thread: an expression field is not thread-safe.
    std::vector<Metric> metrics(nodes.size());
    for (std::size_t i = 0; i < nodes.size(); ++i) metrics[i] = metric.at(nodes.x[i]);
    const Mesh mesh = triangulate_in_metric(nodes, names, metrics);
    if (mesh.triangles.empty()) return s;
    std::vector<double> q = metric_qualities(mesh.points, mesh.triangles, metrics);
    // In ascending Q: the worst triangles first, and both sums in one order for the same triangles.
    std::sort(q.begin(), q.end());
    const std::size_t worst = metric_worst_count(q.size());
    const auto split = q.begin() + static_cast<std::ptrdiff_t>(worst);
    // An inverted triangle (Q <= 0) is no measurement of a settled mesh.
    if (!(q.front() > 0.0)) return s;
    double worst_sum = 0.0;
    for (auto it = q.begin(); it != split; ++it) worst_sum += *it;
    double inverse = 0.0;
    for (auto it = split; it != q.end(); ++it) inverse += 1.0 / *it;
    s.min_angle = 60.0 * worst_sum / static_cast<double>(worst);
    s.aspect_ratio = q.size() > worst ? inverse / static_cast<double>(q.size() - worst) : 1.0 / q.front();
  } catch (const Interrupted&) {
    throw;
  } catch (const Error&) {
    // As measure_mesh: nodes that do not triangulate are not converged.
  }
  return s;
}

ConvergenceMonitor::ConvergenceMonitor(const ConvergenceOptions& options, std::vector<MeshSample> samples)
    : options_(options), samples_(std::move(samples)) {
  check_convergence_options(options_);
}

bool ConvergenceMonitor::due(int iteration) const {
  return options_.enabled && iteration > 0 && iteration % options_.check_every == 0;
}

bool ConvergenceMonitor::observe(const HistoryRow& row, const MeshSample* sample, bool population_settled,
                                 int last_change) {
  if (!sample) return false;
  samples_.push_back(*sample);
  const bool converged = converged_after(row.iteration, population_settled, last_change);
  // PDMESH_CONVERGENCE_TRACE=1: one line per measurement on stderr, with what holds the run (tuning
  // and diagnosis: which condition of the rule decides when a large run stops).
  static const bool trace = std::getenv("PDMESH_CONVERGENCE_TRACE") != nullptr;
  if (trace)
    fmt::print(
        stderr, "convergence after iteration {}: min angle {:.2f} mean aspect ratio {:.5f}; {}\n", row.iteration,
        sample->min_angle, sample->aspect_ratio,
        converged ? std::string("converged") : not_converged_reason(row.iteration, population_settled, last_change));
  return converged;
}

struct ConvergenceMonitor::Verdict {
  enum class Why { Converged, Disabled, Population, Early, NoWindow, NotFinite, Aspect, Angle } why = Why::Disabled;
  int window_start = 0;
  double aspect_change = 0.0, best_before = -1.0, best_within = -1.0;
};

ConvergenceMonitor::Verdict ConvergenceMonitor::judge(int iteration, bool population_settled, int last_change) const {
  using Why = Verdict::Why;
  Verdict v;
  if (!options_.enabled) return v;
  v.why = Why::Population;
  if (!population_settled) return v;
  v.why = Why::Early;
  if (iteration < options_.min_iterations) return v;
  // Only at a measurement: the newest sample must be of this iteration.
  v.why = Why::NoWindow;
  if (samples_.empty() || samples_.back().iteration != iteration) return v;
  const int start = iteration - options_.window;
  v = judge_window(start);
  if (v.why == Why::Converged || !options_.from_last_event || last_change <= start) return v;
  // Or from the first measurement after the event on (a measurement after the event's iteration is
  // taken after the event), over at least one measurement interval.
  const auto after = std::find_if(samples_.begin(), samples_.end(),
                                  [last_change](const MeshSample& s) { return s.iteration >= last_change; });
  if (after == samples_.end() || iteration - after->iteration < options_.check_every) return v;
  const Verdict since_event = judge_window(after->iteration);
  return since_event.why == Why::Converged ? since_event : v;
}

ConvergenceMonitor::Verdict ConvergenceMonitor::judge_window(int start) const {
  using Why = Verdict::Why;
  // The window: the measurements after `start`, and the one at its start.
  Verdict v;
  v.why = Why::NoWindow;
  v.window_start = start;
  const auto first_in =
      std::find_if(samples_.begin(), samples_.end(), [start](const MeshSample& s) { return s.iteration > start; });
  if (first_in == samples_.begin() || (first_in - 1)->iteration != start) return v;
  double aspect_lo = HUGE_VAL, aspect_hi = -HUGE_VAL;
  for (auto it = samples_.begin(); it != samples_.end(); ++it) {
    const bool finite = std::isfinite(it->min_angle) && std::isfinite(it->aspect_ratio);
    if (it >= first_in - 1) {
      // The nodes did not triangulate within the window: not settled.
      if (!finite) return Verdict{Why::NotFinite, start};
      aspect_lo = std::min(aspect_lo, it->aspect_ratio);
      aspect_hi = std::max(aspect_hi, it->aspect_ratio);
    }
    if (!finite) continue;
    if (it < first_in)
      v.best_before = std::max(v.best_before, it->min_angle);
    else
      v.best_within = std::max(v.best_within, it->min_angle);
  }
  v.aspect_change = aspect_hi - aspect_lo;
  // The mean quality has stayed within the tolerance over the window (worsening counts too), and the
  // smallest angle has not reached a new best in it.
  v.why = v.aspect_change > options_.aspect_tolerance                ? Why::Aspect
          : v.best_within > v.best_before + options_.angle_tolerance ? Why::Angle
                                                                     : Why::Converged;
  return v;
}

bool ConvergenceMonitor::converged_after(int iteration, bool population_settled, int last_change) const {
  return judge(iteration, population_settled, last_change).why == Verdict::Why::Converged;
}

std::string ConvergenceMonitor::not_converged_reason(int iteration, bool population_settled, int last_change) const {
  using Why = Verdict::Why;
  const Verdict v = judge(iteration, population_settled, last_change);
  switch (v.why) {
    case Why::Converged:
      return {};
    case Why::Disabled:
      return "the stopping rule is off";
    case Why::Population:
      return "population control had not settled";
    case Why::Early:
      return fmt::format("iteration {} is before the earliest stop ({})", iteration, options_.min_iterations);
    case Why::NoWindow:
      return fmt::format("no measured window of {} iterations ends at iteration {}", options_.window, iteration);
    case Why::NotFinite:
      return fmt::format("the nodes did not triangulate at a measurement after iteration {}", v.window_start);
    case Why::Aspect:
      return fmt::format(
          "the mean aspect ratio of the triangulated nodes changed by {:.2g} over iterations {}-{} (tolerance {:.2g})",
          v.aspect_change, v.window_start, iteration, options_.aspect_tolerance);
    case Why::Angle:
      return fmt::format(
          "the smallest angle reached a new best over iterations {}-{}: {:.2f} deg against {:.2f} before (tolerance "
          "{:.2f})",
          v.window_start, iteration, v.best_within, v.best_before, options_.angle_tolerance);
  }
  return {};
}

}  // namespace pdmesh
