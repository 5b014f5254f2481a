// The cleanup driver: outer iterations of smoothing sweeps and a topology pass over the bad triangles.
#include "cleanup/cleanup.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <set>

#include "core/interrupt.hpp"
#include "cleanup/cleaned_nodes.hpp"
#include "cleanup/editable_mesh.hpp"
#include "cleanup/measures.hpp"
#include "cleanup/mesh_lists.hpp"
#include "cleanup/smoothing.hpp"
#include "cleanup/strip_sweeps.hpp"
#include "cleanup/topology_ops.hpp"
#include "core/parallel.hpp"
#include "nodes/boundary_arcs.hpp"

namespace pdmesh {

using cleanup::EditableMesh;

namespace {

// The scores of the live triangles, for the sweeps' candidate lists. A triangle slot not marked since the
// last call (the journal marks every changed triangle, those of every moved vertex's star among them,
// each mark with the mesh's epoch, which each call ends by advancing) keeps the score computed then,
// which is the score quality() would give: the same triangle, the same points.
// Late iterations change little of a large mesh, and the calls within one iteration (two sweeps, the
// topology pass, settling) score again only what changed in between.
class Scores {
 public:
  explicit Scores(std::size_t threads) : threads_(cleanup::sweep_thread_limit(threads)) {}
  const std::vector<double>& update(EditableMesh& m) {
    const std::uint32_t since = since_;
    // No new slot and no mark since the last call (the sweeps' first list after settling's scan, or
    // settling's scan after a topology pass that changed nothing): every kept score stands.
    if (m.triangle_slots() == known_ && !m.any_marked_in(since)) return score_;
    score_.resize(m.triangle_slots(), 0.0);
    // Each index writes only its own score: the same scores on any number of threads.
    parallel_for(
        static_cast<std::size_t>(m.triangle_slots()),
        [&](std::size_t slot) {
          const int t = static_cast<int>(slot);
          if (!m.alive(t)) return;
          if (t >= known_ || m.triangle_marked_in(t, since)) score_[t] = m.quality(t);
        },
        16384, threads_);
    known_ = m.triangle_slots();
    m.next_epoch();
    since_ = m.epoch();
    return score_;
  }

 private:
  std::vector<double> score_;
  int known_ = 0;            // slots scored by the last update
  std::uint32_t since_ = 0;  // the epoch begun by the last update: marks from then on are new
  std::size_t threads_;
};

// A triangle's vertices in ascending order: its name in the set of triangles no operation could repair.
std::array<int, 3> sorted_key(std::array<int, 3> key) {
  std::sort(key.begin(), key.end());
  return key;
}

// The median of edge length / q(midpoint) over a deterministic sample of at most ~4096 edges. The
// particle lattice settles a little tighter than q (thesis ch. 6: ratios near 0.92), so the size
// guards compare edges with this multiple of q rather than with q itself. Clamped to [0.8, 1]: a mesh
// with gaps or without interior nodes has long edges everywhere, which say nothing about the lattice.
double edge_to_spacing_ratio(const Mesh& mesh, const SpacingField& spacing) {
  std::vector<double> ratios;
  const std::size_t stride = std::max<std::size_t>(1, mesh.triangles.size() / 4096);
  for (std::size_t t = 0; t < mesh.triangles.size(); t += stride) {
    const Vec2 a = mesh.points[mesh.triangles[t][0]], b = mesh.points[mesh.triangles[t][1]];
    const double q = spacing.at(0.5 * (a + b));
    if (q > 0.0 && std::isfinite(q)) ratios.push_back(dist(a, b) / q);
  }
  if (ratios.empty()) return 1.0;
  std::nth_element(ratios.begin(), ratios.begin() + ratios.size() / 2, ratios.end());
  return std::clamp(ratios[ratios.size() / 2], 0.8, 1.0);
}

// The three thresholds of a run, as sines of the smallest angle.
struct Limits {
  double smooth;    // the sweeps work on the vertices of the triangles below this ...
  double topology;  // ... the topology pass on the triangles below this ...
  double target;    // ... and these are the triangles to repair;
  double lift;      // those below this that no topology change repairs get lifting climbs
};

Limits limits_of(const CleanupOptions& options) {
  const double smooth_below =
      options.smooth_below >= 0.0 ? options.smooth_below : std::min(options.min_angle + 20.0, 59.0);
  const double topology_below =
      options.topology_below >= 0.0 ? options.topology_below : std::min(options.min_angle + 15.0, 59.0);
  return {cleanup::sine_from_degrees(smooth_below), cleanup::sine_from_degrees(topology_below),
          cleanup::sine_from_degrees(options.min_angle),
          cleanup::sine_from_degrees(std::min(options.min_angle + options.lift_above, topology_below))};
}

cleanup::TopologyOptions topology_options_of(const CleanupOptions& options, const Limits& limits) {
  cleanup::TopologyOptions topology_options;
  topology_options.target = limits.target;
  topology_options.enough = limits.topology;
  topology_options.split_boundary = options.split_boundary;
  topology_options.compound = options.compound;
  return topology_options;
}

// Adds a sweep's accepted move (if it moved) to the iteration's record.
void tally_move(bool moved, const cleanup::Smoother& smoother, CleanupIteration& record) {
  if (!moved) return;
  cleanup::count_move(record, smoother.last_gain());
}

// The strips of a mesh of `vertices` vertices (CleanupOptions::strip_vertices, small_strip_vertices);
// 0: serial sweeps.
int strips_for(std::size_t vertices, const CleanupOptions& options) {
  if (options.strip_vertices == 0) return 0;
  const std::size_t strips = vertices / options.strip_vertices;
  if (strips >= CleanupOptions::kMinStrips)
    return static_cast<int>(std::min<std::size_t>(strips, CleanupOptions::kMaxStrips));
  const auto small = static_cast<std::size_t>(CleanupOptions::kSmallStrips);
  return options.small_strip_vertices > 0 && vertices >= small * options.small_strip_vertices
             ? CleanupOptions::kSmallStrips
             : 0;
}

// The mesh being cleaned, its smoother and topology operations, and what the outer iterations carry
// from one to the next: the kept scores and the triangles no operation could repair.
class CleanupRun {
 public:
  CleanupRun(const Mesh& mesh, const NodeSet& nodes, const GeometryTree& tree, const SpacingField& spacing,
             const CleanupOptions& options, double ratio)
      : options_(options),
        limits_(limits_of(options)),
        m_(mesh, nodes.curve_nodes, boundary_arcs(tree.geometry(), nodes),
           cleanup::sweep_thread_limit(options.threads)),
        smoother_(m_, tree.geometry(), options.step_cap),
        ops_(
            m_, smoother_, tree.geometry(), [&spacing, ratio](Vec2 p) { return ratio * spacing.at(p); },
            topology_options_of(options, limits_)),
        trial_budget_(static_cast<std::size_t>(
            std::max(options.min_trials, options.trials_per_triangle * static_cast<double>(mesh.triangles.size())))) {
    smoother_.set_sweep_gain(options.move_min_rise, options.move_aspect_drop);
    if (options.lift) smoother_.set_lift(limits_.lift, [this](int t) { return stuck(t); });
    if (options.sharp_corners) m_.set_sharp_corners(options.min_angle);
    if (const int strips = strips_for(mesh.points.size(), options); strips > 0)
      strips_ = std::make_unique<cleanup::StripSweeps>(m_, strips, options.threads);
  }

  // One outer iteration: the smoothing sweeps, then the topology pass; its record goes to `stats`.
  // Returns the number of changes it made (node moves and topology changes).
  std::size_t iterate(int iteration, CleanupStats& stats);
  // Whether the iterations have settled with the one just made (CleanupOptions::settled_aspect_drop).
  bool settled(int iteration, const CleanupIteration& record);
  // The polishing sweeps (CleanupOptions::polish) after the iterations.
  void polish(CleanupStats& stats);

  // The cleaned mesh and its node set, and the topology operations' counts in `result.stats`.
  void finish(const Mesh& mesh, const NodeSet& nodes, const SpacingField& spacing, CleanupResult& result);

 private:
  void sweeps(const std::vector<std::uint8_t>& dirty, InterruptPoll& poll, CleanupIteration& record);
  // The vertices of the live triangles scored below `below`, ascending (the sweeps' lists).
  std::vector<int> bad_vertices(double below);
  std::vector<std::pair<double, int>> topology_list(double below);
  void set_aspect_totals();
  std::size_t topology_pass(InterruptPoll& poll, CleanupIteration& record, CleanupStats& stats);
  // The smallest score, the aspect-ratio sum and the count of the live triangles, and the summed
  // shortfall of the triangles below the target (target score - score).
  struct MeshScan {
    double worst = 1.0, aspect_sum = 0.0, count = 0.0, deficit = 0.0;
  };
  // Over the live triangles, their scores and aspect ratios computed from the mesh.
  MeshScan scan() const;
  void measure(CleanupIteration& record) const;
  void legalize_all();
  // Whether triangle t is stuck (lifting climbs): no topology change could repair it, or it is above
  // the target once the first trial budget is spent, when no topology pass lists it again.
  bool stuck(int t) const {
    return failures_.count(sorted_key(m_.v[t])) > 0 || (unlisted_ && m_.quality(t) >= limits_.target);
  }
  // Called once the first trial budget is spent: the triangles from the target to the lifting level
  // are stuck from now on. Marks their vertices for the next sweeps (their stars may not have changed
  // since they were last tried) and counts them in record.stuck.
  void mark_unlisted(CleanupIteration& record);

  const CleanupOptions& options_;
  const Limits limits_;
  EditableMesh m_;
  cleanup::Smoother smoother_;
  cleanup::TopologyOps ops_;
  const std::size_t trial_budget_;
  std::vector<std::uint8_t> mark_;
  std::vector<double> aspect_;  // set_aspect_totals()'s aspect ratios, by slot
  Scores scores_{options_.threads};
  std::unique_ptr<cleanup::StripSweeps> strips_;  // null: serial sweeps
  std::set<std::array<int, 3>> failures_;
  std::vector<std::uint8_t> since_;  // the dirty marks taken at the start of the iteration
  double last_worst_ = -1.0;         // the smallest score after the previous iteration (settled()) ...
  double last_deficit_ = -1.0;       // ... and the shortfall below the target
  bool unlisted_ = false;            // the first trial budget is spent (mark_unlisted())
  double list_seconds_ = 0.0;        // CleanupStats::list_seconds
  const std::size_t threads_ = cleanup::sweep_thread_limit(options_.threads);  // of the whole-mesh lists
};

// The sweeps over the vertices of the bad triangles: relaxation below the smoothing limit, then
// hill-climbing below the topology limit.
void CleanupRun::sweeps(const std::vector<std::uint8_t>& dirty, InterruptPoll& poll, CleanupIteration& record) {
  // Skipping a node whose neighbourhood did not change since it last failed gives exactly the result
  // of trying it (the same proposal is rejected again); checked when its turn comes, since an earlier
  // move in the same sweep may have changed it.
  auto worth = [&](int a) { return (a < static_cast<int>(dirty.size()) && dirty[a]) || m_.dirty(a); };
  if (strips_) {
    for (const auto move : {cleanup::SweepMove::Relax, cleanup::SweepMove::Climb}) {
      const double below = move == cleanup::SweepMove::Relax ? limits_.smooth : limits_.topology;
      const auto list = bad_vertices(below);
      cleanup::add_moves(record, strips_->sweep(m_, smoother_, list, move, worth, poll));
    }
    return;
  }
  // A vertex whose last move of the same kind left it where it was, with no mark since, is skipped too
  // (EditableMesh::set_unmoved): within an iteration and across them, so a vertex whose star changed
  // before its failed try in the previous iteration, and not after it, is not tried again.
  constexpr std::uint8_t kRelax = 1, kClimb = 2;
  for (int a : bad_vertices(limits_.smooth)) {
    poll.tick();
    if (!worth(a) || m_.unmoved(a, kRelax)) continue;
    const bool moved = smoother_.relax(a);
    if (!moved) m_.set_unmoved(a, kRelax);
    tally_move(moved, smoother_, record);
  }
  for (int a : bad_vertices(limits_.topology)) {
    poll.tick();
    if (!worth(a) || m_.unmoved(a, kClimb)) continue;
    const bool moved = smoother_.climb(a);
    if (!moved) m_.set_unmoved(a, kClimb);
    tally_move(moved, smoother_, record);
  }
}

std::vector<int> CleanupRun::bad_vertices(double below) {
  const auto start = std::chrono::steady_clock::now();
  auto list = cleanup::vertices_of_bad_triangles(m_, scores_.update(m_), below, mark_, threads_);
  list_seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return list;
}

// The live triangles scored below `below` that have not failed before, worst first. Triangles that
// failed before are dropped before the sort rather than after it: after the first pass they are nearly
// all of the list, and the order of the others is the same.
std::vector<std::pair<double, int>> CleanupRun::topology_list(double below) {
  const auto start = std::chrono::steady_clock::now();
  // The scores the sweeps' lists keep, brought up to date: triangles the sweeps did not change keep
  // theirs, rather than every triangle's being computed again.
  const std::vector<double>& score = scores_.update(m_);
  auto bad = cleanup::bad_triangles(
      m_, score, below, [&](int t) { return failures_.empty() || failures_.count(sorted_key(m_.v[t])) == 0; },
      threads_);
  list_seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return bad;
}

// The sum and count of the live triangles' aspect ratios, which the topology operations' gain measures.
// The aspect ratios are computed on several threads, each slot its own; the sum is then taken on one
// thread in slot order, so it is the same number on any thread count.
void CleanupRun::set_aspect_totals() {
  aspect_.resize(static_cast<std::size_t>(m_.triangle_slots()));
  parallel_for(
      aspect_.size(),
      [&](std::size_t slot) {
        const int t = static_cast<int>(slot);
        if (m_.alive(t)) aspect_[slot] = m_.aspect(t);
      },
      16384, cleanup::sweep_thread_limit(options_.threads));
  double aspect_sum = 0.0, count = 0.0;
  for (int t = 0; t < m_.triangle_slots(); ++t)
    if (m_.alive(t)) {
      aspect_sum += aspect_[static_cast<std::size_t>(t)];
      count += 1.0;
    }
  ops_.set_aspect_totals(aspect_sum, count);
}

// The topology pass, worst triangle first. The triangles below the target get compound trials when no
// single one helps, and may spend a second budget: they come first and are few in a settled lattice,
// and the first budget is often gone on the 40-55 degree triangles of the first iterations
// (docs/cleanup.md). So once the first budget is spent only the triangles below the target are listed
// (the pass would stop at the first other one), and a pass with none to try, the common case on a
// settled lattice after its first pass, is not made at all. Returns the number of changes it made.
std::size_t CleanupRun::topology_pass(InterruptPoll& poll, CleanupIteration& record, CleanupStats& stats) {
  const bool first_spent = ops_.trials() >= trial_budget_;
  const auto bad = topology_list(first_spent ? limits_.target : limits_.topology);
  if (!bad.empty()) set_aspect_totals();
  std::size_t changed = 0;
  const std::size_t trials_before = ops_.trials();
  for (const auto& [q, t] : bad) {
    poll.tick();
    const bool below = q < limits_.target;
    if (ops_.trials() >= trial_budget_ && (!below || ops_.trials() >= 2 * trial_budget_)) break;
    if (!m_.alive(t) || !(m_.quality(t) < limits_.topology)) continue;
    // A triangle no operation could repair is not tried again in this run.
    const auto key = sorted_key(m_.v[t]);
    if (failures_.count(key) > 0) continue;
    const double now = m_.quality(t);
    // Compound trials for a triangle below the target now (an earlier repair may have lifted it).
    const cleanup::RepairKind kind = ops_.repair(t, now < limits_.target);
    if (kind == cleanup::RepairKind::None) {
      ++stats.rejected;
      failures_.insert(key);
      // Its vertices get lifting climbs in the next sweeps, which their unchanged stars would skip.
      if (options_.lift && now < limits_.lift) {
        m_.mark_changed(t);
        ++record.stuck;
      }
      continue;
    }
    if (kind == cleanup::RepairKind::Collapse)
      ++stats.collapsed;
    else if (kind != cleanup::RepairKind::Compound)
      ++stats.inserted;  // a compound's nodes are counted in finish()
    ++changed;
    record.trials_to_last_change = ops_.trials() - trials_before;
    record.last_change_angle = cleanup::degrees_from_sine(now);
  }
  record.trials = ops_.trials() - trials_before;
  if (options_.lift && !unlisted_ && ops_.trials() >= trial_budget_) mark_unlisted(record);
  return changed;
}

void CleanupRun::mark_unlisted(CleanupIteration& record) {
  unlisted_ = true;
  for (int t = 0; t < m_.triangle_slots(); ++t) {
    if (!m_.alive(t)) continue;
    const double q = m_.quality(t);
    if (q >= limits_.target && q < limits_.lift) {
      m_.mark_changed(t);
      ++record.stuck;
    }
  }
}

CleanupRun::MeshScan CleanupRun::scan() const {
  MeshScan s;
  for (int t = 0; t < m_.triangle_slots(); ++t)
    if (m_.alive(t)) {
      const double q = m_.quality(t);
      s.worst = std::min(s.worst, q);
      if (q < limits_.target) s.deficit += limits_.target - q;
      s.aspect_sum += m_.aspect(t);
      s.count += 1.0;
    }
  return s;
}

// The whole mesh's smallest angle and mean aspect ratio after an iteration.
void CleanupRun::measure(CleanupIteration& record) const {
  const MeshScan s = scan();
  record.min_angle = cleanup::degrees_from_sine(s.worst);
  record.aspect_mean = s.count > 0.0 ? s.aspect_sum / s.count : 0.0;
  record.deficit = s.deficit;
}

// Quiet: no topology change, and the sweeps neither raised the smallest score nor lifted any triangle
// below the target (the shortfall below it did not shrink), and lowered the mean aspect ratio by less
// than the setting. A cleanup whose sweeps still lift triangles below the target goes on however little
// the mean aspect ratio moves (a mesh that cannot reach the target, or whose worst triangles rise slowly).
bool CleanupRun::settled(int iteration, const CleanupIteration& record) {
  if (!(options_.settled_aspect_drop > 0.0)) return false;
  // The kept scores brought up to date (only the triangles the iteration changed are scored again):
  // the values quality() gives, without a scan of every triangle's angles per iteration.
  const cleanup::ScoreScan s = cleanup::scan_scores(m_, scores_.update(m_), limits_.target, threads_);
  const bool quiet = iteration > 0 && record.topology == 0 && record.stuck == 0 && s.worst <= last_worst_ &&
                     s.deficit >= last_deficit_ && record.aspect_drop < options_.settled_aspect_drop * s.count;
  last_worst_ = s.worst;
  last_deficit_ = s.deficit;
  return quiet;
}

// Lawson flips over every edge of the mesh. Each edit legalises the edges it can make illegal but one:
// an edge collapse moves the kept node and legalises only its link, not its spokes, and a spoke left
// illegal there is mostly flipped by a later move of the node or of a neighbour, but not always (the
// user corpus's square_circle_hole). A mesh that is constrained Delaunay already flips nothing here,
// which the test on several threads finds without the list of every edge.
void CleanupRun::legalize_all() {
  if (m_.locally_delaunay(cleanup::sweep_thread_limit(options_.threads))) return;
  std::vector<cleanup::EdgeRef> edges;
  for (int t = 0; t < m_.triangle_slots(); ++t)
    if (m_.alive(t))
      for (int i = 0; i < 3; ++i) edges.push_back({m_.v[t][pdmesh::next3(i)], m_.v[t][pdmesh::prev3(i)], t});
  m_.legalize(edges);
}

std::size_t CleanupRun::iterate(int iteration, CleanupStats& stats) {
  // Only nodes whose neighbourhood changed since the last sweep can propose something new.
  since_ = m_.take_dirty();
  const std::vector<std::uint8_t>& dirty = since_;
  const auto timer = std::chrono::steady_clock::now();
  CleanupIteration record;
  // A stop request ends the cleanup between two node moves or repairs (each leaves a valid mesh).
  InterruptPoll poll(256);
  sweeps(dirty, poll, record);
  const auto smoothed = std::chrono::steady_clock::now();
  record.smoothing_seconds = std::chrono::duration<double>(smoothed - timer).count();
  stats.smoothing_seconds += record.smoothing_seconds;
  stats.moves += record.moves;
  // Not in the last iteration, which only smooths.
  if (options_.topology && iteration + 1 < options_.iterations && ops_.trials() < 2 * trial_budget_) {
    record.topology = topology_pass(poll, record, stats);
    record.topology_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - smoothed).count();
    stats.topology_seconds += record.topology_seconds;
  }
  if (options_.measure_iterations) measure(record);
  stats.per_iteration.push_back(record);
  stats.iterations_run = iteration + 1;
  // A triangle newly found stuck below the target gets its lifting climbs in the next iteration.
  return record.moves + record.topology + record.stuck;
}

void CleanupRun::polish(CleanupStats& stats) {
  InterruptPoll poll(256);
  // The first sweep tries every node (the repairs' sweeps tried only those of bad triangles); later
  // ones only the nodes whose star changed since, which alone can propose something new.
  m_.take_dirty();
  std::vector<std::uint8_t> worth(static_cast<std::size_t>(m_.vertex_slots()), 1);
  for (int sweep = 0; sweep < options_.polish; ++sweep) {
    std::size_t moved = 0;
    for (int a = 0; a < m_.vertex_slots(); ++a) {
      poll.tick();
      if (static_cast<std::size_t>(a) < worth.size() && worth[a] && smoother_.relax(a)) ++moved;
    }
    stats.polish_sweeps = sweep + 1;
    stats.polish_moves += moved;
    stats.moves += moved;
    if (moved == 0) break;
    worth = m_.take_dirty();
  }
}

void CleanupRun::finish(const Mesh& mesh, const NodeSet& nodes, const SpacingField& spacing, CleanupResult& result) {
  const auto start = std::chrono::steady_clock::now();
  result.stats.list_seconds = list_seconds_;
  if (strips_) {
    result.stats.strip_serial_seconds = strips_->serial_seconds();
    result.stats.strips = strips_->strips();
    result.stats.strip_taken = strips_->taken();
    result.stats.strip_left = strips_->left();
    result.stats.strip_seconds = strips_->parallel_seconds();
  }
  result.stats.trials = ops_.trials();
  result.stats.inserted += ops_.compound_inserted();
  result.stats.collapsed += ops_.compound_removed();
  result.stats.compound_trials = ops_.compound_trials();
  result.stats.compound_applied = ops_.compound_applied();
  legalize_all();
  cleanup::cleaned_mesh_and_nodes(m_, mesh, nodes, spacing, result.mesh, result.nodes);
  result.stats.finish_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

CleanupResult clean_mesh(const Mesh& mesh, const NodeSet& nodes, const GeometryTree& tree, const SpacingField& spacing,
                         const CleanupOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  CleanupResult result;
  CleanupRun run(mesh, nodes, tree, spacing, options, edge_to_spacing_ratio(mesh, spacing));
  result.stats.setup_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  for (int iteration = 0; iteration < options.iterations; ++iteration) {
    if (run.iterate(iteration, result.stats) == 0) break;
    if (run.settled(iteration, result.stats.per_iteration.back())) {
      result.stats.settled = true;
      break;
    }
  }
  run.polish(result.stats);
  run.finish(mesh, nodes, spacing, result);
  result.stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

}  // namespace pdmesh
