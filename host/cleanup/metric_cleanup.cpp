// The driver of the cleanup in a metric (metric_cleanup.hpp).
#include "cleanup/metric_cleanup.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include "cleanup/cleaned_nodes.hpp"
#include "cleanup/editable_mesh.hpp"
#include "cleanup/metric_evaluator.hpp"
#include "core/interrupt.hpp"
#include "nodes/boundary_arcs.hpp"

namespace pdmesh {

namespace {

// Flip passes after each edit pass: flips raise the smallest Q of a quadrilateral, so few are needed.
constexpr int kFlipRounds = 8;
// The climb works on the nodes of the triangles below this Q.
constexpr double kClimbBelow = 0.8;
// An outer iteration without splits or collapses that leaves the smallest Q where it was and moves the
// mean Q by less than this has settled the mesh: the later ones only shave the edges' lengths.
constexpr double kSettledMeanQ = 1e-4;
// So many outer iterations in a row that leave the smallest Q where it was end the cleanup even with
// edits left: near a curved wall a few splits and collapses can undo each other every iteration, and
// would otherwise run it to its cap without changing the worst triangle.
constexpr int kStalledIterations = 8;

// The smallest and the mean Q of the live triangles.
struct QualityLevel {
  double min = 0.0, mean = 0.0;
};

QualityLevel quality_level(const cleanup::EditableMesh& m) {
  QualityLevel out{std::numeric_limits<double>::infinity(), 0.0};
  std::size_t count = 0;
  for (int t = 0; t < m.triangle_slots(); ++t) {
    if (!m.alive(t)) continue;
    const double q = m.quality(t);
    out.min = std::min(out.min, q);
    out.mean += q;
    ++count;
  }
  if (count > 0) out.mean /= static_cast<double>(count);
  return out;
}

}  // namespace

MetricCleanupResult clean_mesh_in_metric(const Mesh& mesh, const NodeSet& nodes, const GeometryTree& tree,
                                         const SpacingField& spacing, const MetricField& metric,
                                         const MetricCleanupOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  cleanup::EditableMesh m(mesh, nodes.curve_nodes, boundary_arcs(tree.geometry(), nodes));
  const cleanup::MetricEvaluator evaluator(m, metric);
  m.set_score(&evaluator);
  cleanup::MetricOpsOptions ops_options;
  ops_options.split_boundary = options.split_boundary;
  cleanup::MetricOps ops(m, evaluator, tree.geometry(), ops_options);
  MetricCleanupResult result;
  // A stop request ends the cleanup between two iterations (each leaves a valid mesh).
  InterruptPoll poll(1);
  QualityLevel level = quality_level(m);
  int stalled = 0;  // iterations in a row that did not raise the smallest Q
  for (int iteration = 0; iteration < options.iterations; ++iteration) {
    poll.tick();
    std::size_t changes = 0, edits = 0;
    if (options.topology) {
      edits += ops.split_long();
      changes += ops.flip_all(kFlipRounds);
      edits += ops.collapse_short();
    }
    changes += edits + ops.flip_all(kFlipRounds);
    for (int sweep = 0; sweep < options.smoothing_sweeps; ++sweep) {
      const std::size_t moved = ops.smooth();
      changes += moved + ops.flip_all(kFlipRounds);
      if (moved == 0) break;
    }
    for (int sweep = 0; sweep < options.smoothing_sweeps; ++sweep) {
      const std::size_t moved = ops.climb(kClimbBelow);
      changes += moved + ops.flip_all(kFlipRounds);
      if (moved == 0) break;
    }
    result.stats.iterations_run = iteration + 1;
    if (changes == 0) break;
    const QualityLevel now = quality_level(m);
    const bool raised = now.min > level.min;
    stalled = raised ? 0 : stalled + 1;
    const bool settled = edits == 0 && !raised && std::fabs(now.mean - level.mean) < kSettledMeanQ;
    level = now;
    if (settled || stalled >= kStalledIterations) break;
  }
  cleanup::cleaned_mesh_and_nodes(m, mesh, nodes, spacing, result.mesh, result.nodes);
  result.metrics.reserve(result.mesh.points.size());
  for (const Vec2& p : result.mesh.points) result.metrics.push_back(metric.at(p));
  result.stats.counts = ops.counts();
  result.stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

}  // namespace pdmesh
