// The device-resident run's iterations, in sim/iteration_loop's loop (DeviceRun is its IterationSteps);
// see device_simulation.hpp and docs/opencl.md. Per iteration:
// [rebuild the Verlet lists when the skin is used up] -> device_step (forces, r0, time step, move,
// spacing, clearance budgets, partial sums) -> boundary_snap (every boundary node re-snapped on the
// device, kernels/boundary.cl) -> download the partials and the flagged interior candidates -> the
// host's exact test on those only -> [apply_host_moves for them] -> dt rule on the host.
#include "opencl/device_run.hpp"

#include <algorithm>
#include <cmath>
#include <thread>
#include <utility>

#include "core/errors.hpp"
#include "core/free_memory.hpp"
#include "core/interrupt.hpp"
#include "sim/failure_report.hpp"
#include "sim/reference/reference_backend.hpp"
#include "spacing/background_field.hpp"

namespace pdmesh::ocl {

template <typename Real>
void DeviceRun<Real>::rebuild(bool read_state) {
  const std::size_t n = n_;
  std::vector<Real>* v = positions_host_;
  // The host's copy of the build state, for the saved state (remember, which the host's skin test
  // reads); the binning does not read it, so it is read after the build, once the build's scratch is
  // freed (the two together would add to a build's peak). The first build's is the state just
  // uploaded (nodes_).
  const bool read_back = stats_.rebuilds > 0;
  auto read_build_state = [&] {
    read(xy_[cur_], v[0], 2 * n, false);
    read(q_[cur_], v[1], n);
  };
  const double radius = options_.cutoff * (1.0 + options_.verlet_skin);
  NeighbourFlags flags =
      neighbours_.build(n, radius, xy_[cur_], q_[cur_], kind_, prev_, next_, options_.verlet_skin * options_.cutoff);
  if (flags.first_invalid >= 0) {
    if (read_back) read_build_state();
    const auto i = static_cast<std::size_t>(flags.first_invalid);
    const double x = read_back ? static_cast<double>(v[0][2 * i]) : nodes_.x[i].x;
    const double y = read_back ? static_cast<double>(v[0][2 * i + 1]) : nodes_.x[i].y;
    const double q = read_back ? static_cast<double>(v[1][i]) : nodes_.q[i];
    throw SimulationError(fmt::format("node {} is invalid before binning: x = ({}, {}), q = {}", i, x, y, q));
  }
  // The grids, levels, spill and move lists are the build's own (the step reads the rows): freed until
  // the next build, so that they never sit beside a convergence check's triangulation.
  neighbours_.release_build_scratch();
  if (read_back && read_state) read_build_state();
  largest_row_ = std::max(largest_row_, flags.max_count);
  stats_.gather_seconds += neighbours_.gather_seconds;
  stats_.gathers += neighbours_.attempts;
  stats_.outgrown_rows += neighbours_.outgrown_rows;
  stats_.sampled_builds += neighbours_.sampled ? 1 : 0;
  stats_.bytes_up += neighbours_.uploaded_bytes;
  stats_.launches += static_cast<std::size_t>(neighbours_.launches);  // the row sizing, gather and sort
  pairs_examined_ += flags.pairs_examined;
  stats_.rebuild_candidates += flags.pairs_examined;
  stats_.pairs_listed += flags.pairs_within;
  list_entries_ = flags.pairs_within;
  skin_limit_ = skin_use_limit(neighbours_.spacing_ratio);
  stats_.largest_spacing_ratio = std::max(stats_.largest_spacing_ratio, neighbours_.spacing_ratio);
  // The host's test of the nodes it moves needs their classes: read with the next wait (a window's).
  read(neighbours_.skin_class(), skin_class_host_, n, false);
  // The build state the skin is measured from.
  copy_buffer(ctx_.queue(), xy_[cur_].get(), xy_build_.get(), 2 * n * sizeof(Real), "copy to the build state");
  copy_buffer(ctx_.queue(), q_[cur_].get(), q_build_.get(), n * sizeof(Real), "copy to the build state");
  ++stats_.rebuilds;
  skin_use_ = 0.0;
}

// One iteration's kernels from buffers `cur`: device_step (dt^2 from window_.dt2()) and boundary_snap;
// with the device's rule, boundary_snap_rule instead (the rule in its last work-group), or iteration_rule
// where there are no boundary nodes. Nothing is waited on.
template <typename Real>
void DeviceRun<Real>::enqueue_iteration(int cur) {
  const int next = 1 - cur;
  ArgSetter a(program_.device_step, "device_step");
  a(static_cast<cl_int>(n_))(static_cast<Real>(options_.cutoff))(static_cast<Real>(options_.lj_a))(
      static_cast<cl_int>(options_.r0_any_direction ? 1 : 0))(static_cast<Real>(options_.stability_factor))(
      window_.dt2())(static_cast<Real>(options_.verlet_skin * options_.cutoff))(xy_[cur])(q_[cur])(
      kind_)(tx_)(ty_)(neighbours_.count())(neighbours_.offset())(neighbours_.index())(
      xy_build_)(q_build_)(neighbours_.skin_class())(bslot_)(xy_[next])(q_[next])(
      budget_)(node_leaf_)(brec_)(cand_index_)(cand_rec_)(counters_)(partials_)(device_boundary_.segments())(
      static_cast<cl_int>(device_boundary_.segment_count()))(static_cast<Real>(device_boundary_.segment_scale()))(
      static_cast<Real>(options_.momentum))(static_cast<Real>(options_.momentum_mix))(carried_);
  bg_args(a);
  launch(ctx_.queue(), program_.device_step, "device_step", n_, program_.work_group);
  ++stats_.launches;
  if (program_.force_loop == ForceLoop::Scalar) {  // PDMESH_REFRESH_KERNEL: the clearance refresh apart
    ArgSetter r(program_.refresh_budgets, "refresh_budgets");
    r(static_cast<cl_int>(n_))(counters_)(cand_index_)(cand_rec_)(budget_)(q_[next])(
        xy_build_)(q_build_)(neighbours_.skin_class())(static_cast<Real>(options_.cutoff))(
        static_cast<Real>(options_.verlet_skin * options_.cutoff))(device_boundary_.segments())(static_cast<cl_int>(
        device_boundary_.segment_count()))(static_cast<Real>(device_boundary_.segment_scale()))(partials_);
    launch(ctx_.queue(), program_.refresh_budgets, "refresh_budgets", n_, program_.work_group);
    ++stats_.launches;
  }
  // Every boundary node re-snapped on the device into the next buffers (x, y, q, tangents, arcs); with
  // the device's rule, the same launch ends the iteration (boundary_snap_rule).
  auto rule = [this](ArgSetter& a) { window_.rule_args(a, groups(), partials_); };
  bool rule_done = false;
  if (!boundary_nodes_.empty() &&
      device_boundary_.enqueue(
          program_, cur, brec_, xy_[next], q_[next], tx_, ty_, node_leaf_, xy_build_, q_build_,
          neighbours_.skin_class(), options_.cutoff, options_.verlet_skin * options_.cutoff, counters_,
          [this](ArgSetter& a) { bg_args(a); }, window_.device_rule() ? &rule : nullptr)) {
    ++stats_.launches;
    rule_done = window_.device_rule();
  }
  if (window_.device_rule() && !rule_done) {
    window_.enqueue_rule(program_, groups(), partials_, device_boundary_.partial_count(program_.work_group),
                         device_boundary_.partials(), counters_);
    ++stats_.launches;
  }
}

// One whole window from iteration `first`, waited for: begin_window, then end_window.
template <typename Real>
void DeviceRun<Real>::start_window(int first, const GlobalTimeStep& gm) {
  begin_window(first, gm, window_.max_length());
  end_window();
}

// Enqueues iterations first .. (at most) the window's end, and no more than `most`, and the reads of
// their rows, without a wait. The window ends where the host has work whatever the device does: a
// population event, a convergence measurement, the last iteration; a zero skin rebuilds every iteration.
template <typename Real>
void DeviceRun<Real>::begin_window(int first, const GlobalTimeStep& gm, int most) {
  int last = first;
  const int cap = options_.verlet_skin == 0.0
                      ? first
                      : std::min(options_.iterations, first + std::min(window_length(), std::max(1, most)) - 1);
  while (last < cap && !loop_.convergence().due(last) &&
         !population_event_due(options_.population, loop_.population().schedule, last, options_.iterations))
    ++last;
  pending_t0_ = Clock::now();
  window_.begin(gm, skin_use_, skin_limit_, counters_);
  for (int k = 0; k <= last - first; ++k) enqueue_iteration(cur_ ^ (k & 1));
  window_.enqueue_reads(ctx_, groups(), partials_, device_boundary_.partial_count(program_.work_group),
                        device_boundary_.partials(), counters_);
  window_pending_ = true;
  pending_first_ = first;
  pending_length_ = last - first + 1;
}

// Waits for the window begin_window enqueued and takes its rows (one wait).
template <typename Real>
void DeviceRun<Real>::end_window() {
  window_pending_ = false;
  window_rows_ = window_.complete(ctx_, groups(), device_boundary_.partial_count(program_.work_group));
  window_next_ = 0;
  ++stats_.windows;
  stats_.transfers += window_.transfers;
  stats_.bytes_up += window_.bytes_up;
  stats_.bytes_down += window_.bytes_down;
  const double seconds = since(pending_t0_);
  stats_.step_seconds += seconds;
  if (window_rows_ >= 1) seconds_per_iteration_ = seconds / window_rows_;
  if (window_rows_ < 1 || window_rows_ > pending_length_)
    throw SimulationError(fmt::format("iteration {}: the device ran {} of the window's {} iterations", pending_first_,
                                      window_rows_, pending_length_));
}

// Iterations the next window enqueues: the most the ring holds, but not far past where the skin is
// expected to run out, since the iterations a halt leaves behind are launched for nothing. The
// prediction: the skin use so far at its mean rate since the build, or right after a build the
// previous build's interval. On a CPU device (PoCL) a launch for nothing costs more than another wait
// (the device's work-groups are scheduled by the host's threads), so the window stops short of the
// prediction; elsewhere a wait costs more, so it reaches one iteration past it. In a settled run
// builds are far apart and windows are whole. A window is also no longer than options_.window_seconds at
// the last window's pace, so that a stop request, acted on at a window's end, waits little at any size.
template <typename Real>
int DeviceRun<Real>::window_length() const {
  if (check_rows_) return 1;
  int most = window_.max_length();
  if (seconds_per_iteration_ > 0.0 && options_.window_seconds > 0.0)
    most = static_cast<int>(
        std::clamp(std::floor(options_.window_seconds / seconds_per_iteration_), 1.0, static_cast<double>(most)));
  double predicted = 0.0;
  if (since_build_ > 0 && skin_use_ > 0.0 && skin_use_ <= skin_limit_)
    predicted = (skin_limit_ - skin_use_) * since_build_ / skin_use_;
  else if (build_interval_ > 0)
    predicted = build_interval_ - since_build_;
  else
    return most;
  const double length = cpu_device_ ? std::floor(0.9 * predicted) : std::ceil(predicted) + 1.0;
  return length >= most ? most : std::max(1, static_cast<int>(length));
}

// A history row's sums (the ring's layout, kernels/window.cl) into the iteration's.
template <typename Real>
void DeviceRun<Real>::take_row_sums(const double* r) {
  sum_force_ = r[kRingForce];
  sum_kinetic_ = r[kRingKinetic];
  sum_moving_ = static_cast<std::size_t>(r[kRingMoving]);
  within_ = static_cast<std::size_t>(r[kRingWithin]);
  coincident_ = static_cast<std::size_t>(r[kRingCoincident]);
  max_force_ = r[kRingMaxForce];
  device_skin_use_ = r[kRingSkin];
  snap_ = BoundarySnapResult{static_cast<std::size_t>(r[kRingClamped]), static_cast<std::size_t>(r[kRingSnapBad]),
                             r[kRingSnapSkin]};
}

// The next row of the window into the iteration's sums, and (the window's last row only) the interior
// nodes for the host's exact test (a second wait).
template <typename Real>
void DeviceRun<Real>::take_row() {
  const double* r = window_.row(window_next_++);
  row_dt_ = r[kRingDt];
  row_entries_ = list_entries_;
  row_held_ = false;
  take_row_sums(r);
  const auto m = static_cast<std::size_t>(r[kRingCandidates]);
  const bool non_finite_move = r[kRingNonFinite] != 0.0;
  if (!boundary_nodes_.empty() && !non_finite_move) {  // boundary_snap wrote the next buffers
    boundary_stale_ = true;
    snap_arcs_ = 1 - cur_;
  }
  auto t0 = Clock::now();
  std::vector<std::int32_t>& cand = cand_index_host_;
  if (m > 0) {
    read(cand_index_, cand, m, false);
    read(cand_rec_, cand_rec_host_, 4 * m, false);
    finish(ctx_.queue(), "device_step candidates");
  }
  stats_.download_seconds += since(t0);
  // Candidates in index order (the reference handles interior nodes in index order); entries ~i < 0
  // are nodes refresh_budgets gave a fresh budget on the device (the GPU shape), not candidates.
  std::vector<std::size_t> order;
  order.reserve(m);
  for (std::size_t k = 0; k < m; ++k)
    if (cand[k] >= 0) order.push_back(k);
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return cand[a] < cand[b]; });
  candidates_.resize(order.size());
  moves_.resize(order.size());
  for (std::size_t k = 0; k < order.size(); ++k) {
    const std::size_t o = order[k];
    const auto i = static_cast<std::size_t>(cand[o]);
    candidates_[k] = cand[o];
    nodes_.x[i] = {static_cast<double>(cand_rec_host_[4 * o]), static_cast<double>(cand_rec_host_[4 * o + 1])};
    moves_[k] = {static_cast<double>(cand_rec_host_[4 * o + 2]), static_cast<double>(cand_rec_host_[4 * o + 3])};
  }
  stats_.candidates += order.size();
  // Every move must be finite (the sums may not show a single NaN move): boundary_snap counted the
  // boundary nodes' targets, the candidates' moves are here.
  moves_finite_ = snap_.non_finite == 0 && !non_finite_move;
  // boundary_snap updated the tangents in place: the device's state before this step is no longer
  // whole, unless the flag stopped it (last_good_state).
  tangents_ahead_ = !boundary_nodes_.empty() && !non_finite_move;
  for (const Vec2 d : moves_) moves_finite_ = moves_finite_ && std::isfinite(d.x) && std::isfinite(d.y);
}

template <typename Real>
void DeviceRun<Real>::check_rows_hold(int iteration) {
  if constexpr (!std::is_same_v<Real, double>) {
    throw SimulationError("PDMESH_TEST_CHECK_ROWS needs a double run (the test compares distances in double)");
  } else {
    if (stats_.rebuilds == 0) return;  // no rows yet: the first iteration builds them
    finish(ctx_.queue(), "the rows' check");
    SimParticles p;
    p.resize(n_);
    std::vector<Real> xy, q;
    xy_[cur_].download(ctx_.queue(), xy, 2 * n_);
    q_[cur_].download(ctx_.queue(), q, n_);
    std::vector<std::int32_t> count, index;
    std::vector<std::uint64_t> offset;
    neighbours_.count().download(ctx_.queue(), count, n_);
    neighbours_.offset().download(ctx_.queue(), offset, n_ + 1);
    neighbours_.index().download(ctx_.queue(), index);
    for (std::size_t i = 0; i < n_; ++i) {
      p.x[i] = xy[2 * i];
      p.y[i] = xy[2 * i + 1];
      p.q[i] = q[i];
      p.kind[i] = kind_host_[i];
    }
    // A stride past every row: a reference row longer than the device's lacks a pair (overflow).
    NeighbourList exact;
    exact.stride = 1 + (count.empty() ? 0 : std::max(0, *std::max_element(count.begin(), count.end())));
    NeighbourFlags flags;
    reference::build_neighbours(p, options_.cutoff, exact, flags);
    const auto stride = static_cast<std::size_t>(exact.stride);
    for (std::size_t i = 0; i < n_; ++i) {
      if (p.kind[i] != kSimInterior) continue;
      const auto begin = index.begin() + static_cast<std::ptrdiff_t>(offset[i]);
      const auto end = begin + count[i];
      if (exact.count[i] > count[i])
        throw SimulationError(fmt::format("iteration {}: node {} has {} pairs within the cut-off, its row {} entries",
                                          iteration, i, exact.count[i], count[i]));
      for (std::size_t k = 0; k < static_cast<std::size_t>(exact.count[i]); ++k) {
        const std::int32_t j = exact.index[i * stride + k];
        if (!std::binary_search(begin, end, j))
          throw SimulationError(fmt::format(
              "iteration {}: node {}'s row ({} entries) lacks node {} at distance {}, within its cut-off {} "
              "({} q, q = {}), {} iterations after the build",
              iteration, i, count[i], j,
              std::hypot(p.x[static_cast<std::size_t>(j)] - p.x[i], p.y[static_cast<std::size_t>(j)] - p.y[i]),
              options_.cutoff * p.q[i], options_.cutoff, p.q[i], since_build_));
      }
    }
  }
}

template <typename Real>
BoundaryCounts DeviceRun<Real>::host_boundary(double& skin_use) {
  auto t0 = Clock::now();
  host_ahead_ = true;
  // The device re-snapped the boundary nodes; a snap reads their arc positions (after the re-snap).
  BoundaryCounts counts = boundary_.apply_interior(nodes_, candidates_, moves_, [this] {
    if (boundary_stale_) sync_boundary();
  });
  counts.clamped = snap_.clamped;
  skin_use = std::max(skin_use, snap_.skin_use);
  if (counts.snapped > 0) {
    upload_topology();  // kinds and curve neighbours changed (rare); apply() forces a rebuild
    // A snapped node's interior motion does not carry over (the host driver's rule). The window
    // halted for the exact test, so the carried moves are this iteration's.
    if (with_momentum()) {
      std::vector<std::int32_t> snapped;
      for (std::int32_t node : candidates_)
        if (nodes_.kind[static_cast<std::size_t>(node)] == NodeKind::Boundary) snapped.push_back(node);
      reset_momentum(snapped);
    }
  }
  // Records: every candidate (moved, or snapped with its tangent).
  // Members: their uploads are non-blocking and complete before the next step's records arrive.
  std::vector<std::int32_t>& index = rec_index_host_;
  std::vector<Real>& rec = rec_host_;
  index.clear();
  rec.clear();
  index.reserve(candidates_.size());
  rec.reserve(5 * index.capacity());
  auto add = [&](std::int32_t node) {
    const auto i = static_cast<std::size_t>(node);
    const Vec2 p = nodes_.x[i], t = boundary_.tangent(node);
    const double budget =
        nodes_.kind[i] == NodeKind::Interior ? device_budget(p, boundary_.clearance_budget(node)) : 0.0;
    index.push_back(node);
    for (double v : {p.x, p.y, t.x, t.y, budget}) rec.push_back(static_cast<Real>(v));
    // The position and q at the last build: the saved state's (the candidates were interior nodes then).
    const Vec2 b = saved_nodes_.x[i];
    const double qb = saved_nodes_.q[i];
    const double ex = p.x - b.x, ey = p.y - b.y;
    const double q = background_.at(p);
    const double grow = q > qb ? options_.cutoff * (q - qb) : 0.0;
    skin_use =
        std::max(skin_use, (std::sqrt(ex * ex + ey * ey) + grow) / (options_.verlet_skin * options_.cutoff * qb) *
                               skin_class_factor(skin_class_host_[i]));
  };
  for (std::int32_t node : candidates_) add(node);
  stats_.host_seconds += since(t0);
  t0 = Clock::now();
  if (!index.empty()) {
    ensure_size(ctx_, rec_index_, "rec_index", index.size());
    ensure_size(ctx_, rec_, "rec", rec.size());
    write(rec_index_, index, false);
    write(rec_, rec, false);
    const int next = 1 - cur_;
    ArgSetter a(program_.apply_host_moves, "apply_host_moves");
    a(static_cast<cl_int>(index.size()))(rec_index_)(rec_)(xy_[next])(q_[next])(tx_)(ty_)(budget_)(node_leaf_);
    bg_args(a);
    launch(ctx_.queue(), program_.apply_host_moves, "apply_host_moves", index.size(), program_.work_group);
    ++stats_.launches;  // not waited on: the next device_step follows it in the in-order queue
  }
  stats_.upload_seconds += since(t0);
  return counts;
}

template <typename Real>
SimResult DeviceRun<Real>::run(const SimCallbacks& callbacks) {
  // The device run acts on a stop request at the end of a window (may_stop); the host work between
  // (boundary handling, population events, the stopping rule's measurement) must not end half way
  // with Interrupted.
  const InterruptShield shield;
  if (!(options_.verlet_skin >= 0.0))
    throw InputError(fmt::format("the Verlet skin must be >= 0, got {}", options_.verlet_skin));
  if (options_.resume)  // before upload_initial reads the tangents
    boundary_.restore(nodes_, options_.resume->arcs, options_.resume->tangents);
  check_memory(0);  // before the first device allocation
  neighbours_.check_entries = [this](std::uint64_t entries) { check_memory(entries); };  // and before the rows grow
  upload_initial();  // setup, like the host path's, is not part of the timed iterations
  stats_.setup_bytes = stats_.bytes_up;
  stats_.bytes_up = 0;
  stats_.transfers = 0;
  fixed_ = nodes_.count(NodeKind::Fixed);
  on_boundary_ = nodes_.count(NodeKind::Boundary);
  interior_ = nodes_.count(NodeKind::Interior);
  remember();
  // On any failure from here on the caller gets the last good state (SimCallbacks::on_failure).
  return loop_.run(*this, callbacks, FailureScope::Run);
}

template <typename Real>
std::string DeviceRun<Real>::backend_name() const {
  return fmt::format("opencl:{}:{} ({}, {}, device-resident)", ctx_.device().platform, ctx_.device().device,
                     ctx_.device().name, std::is_same_v<Real, double> ? "double" : "float");
}

// The lists' rebuild before the iteration after loop_.done(), when the skin is used up. A zero skin
// rebuilds every iteration (the reference's behaviour).
template <typename Real>
bool DeviceRun<Real>::rebuild_if_due(int next_iteration) {
  if (!(skin_use_ > skin_limit_ || options_.verlet_skin == 0.0)) return false;
  // The device halts a window where the skin is used up, so no row of it is left here (and the run
  // ahead of a measurement begins none before a build).
  if (window_next_ < window_rows_ || window_pending_)
    throw SimulationError(fmt::format("iteration {}: a rebuild is due with {} device iterations unread", next_iteration,
                                      window_rows_ - window_next_));
  const CommandCounts before = command_counts();
  const bool read_back = stats_.rebuilds > 0;  // rebuild reads the build state back (in float: not the same as nodes_)
  rebuild();
  if (boundary_stale_) sync_boundary();  // the saved state needs the boundary's
  remember();
  saved_is_build_state_ = std::is_same_v<Real, double> || read_back;
  stats_.rebuild_commands = stats_.rebuild_commands + (command_counts() - before);
  if (stats_.rebuilds > 1) build_interval_ = since_build_;
  since_build_ = 0;
  return true;
}

// The iteration's computation: the next row of the current window, or of a new one.
template <typename Real>
IterationStep DeviceRun<Real>::compute(int iteration, const GlobalTimeStep& gm) {
  if (ahead_used_) go_on_after_ahead();
  // After a check the device ran ahead of, when the run goes on (a run that stops there needs none).
  restore_saved_positions();
  if (ahead_builds_ > 0 && iteration == ahead_build_at_) remember_build_ahead();
  if (held_next_ < held_.size()) {
    take_held_row();
  } else {
    // A window begun ahead of a measurement was preceded by the build it needed (before_measure or
    // run_ahead), and its rows are not read yet: a zero skin, always due, must not build again under it.
    if (!window_pending_ && !ahead_window_) rebuild_if_due(iteration);
    ahead_window_ = false;
    if (window_pending_) {  // begun while the host measured the last iteration's mesh
      end_window();
      host_ahead_ = false;  // as at the start of every iteration: the device holds the state after loop_.done()
      // The run goes on past the check: its carried moves are no state of it any more.
      std::vector<Real>().swap(momentum_at_check_);
      check_momentum_saved_ = false;
    } else if (window_next_ >= window_rows_) {
      if (check_rows_) check_rows_hold(iteration);
      start_window(iteration, gm);
    }
    take_row();
    ++since_build_;
  }
  check_row(iteration, gm.dt());
  // The step kernel computes the distance of every list entry.
  return IterationStep{StepSums{sum_moving_, sum_force_, max_force_, sum_kinetic_}, row_entries_, within_, coincident_};
}

// The measurement is taken: run_ahead stops after its window or build (unless told to run to where the
// host must act: the tests' PDMESH_MEASURE_OVERLAP=full).
template <typename Real>
void DeviceRun<Real>::after_measure() {
  if (overlap_ != MeasureOverlap::Full) ahead_stop_ = true;
}

template <typename Real>
void DeviceRun<Real>::join_ahead() {
  if (!ahead_thread_.joinable()) return;
  ahead_thread_.join();
}

template <typename Real>
void DeviceRun<Real>::run_ahead(int first, GlobalTimeStep gm) {
  const auto stopping = [this] {
    return (overlap_ != MeasureOverlap::Full && ahead_stop_.load()) || (options_.stop && options_.stop->load());
  };
  try {
    for (int next = first;;) {
      begin_window(next, gm, window_.max_length());
      ++stats_.ahead_windows;
      end_window();
      const int last = next + window_rows_ - 1;
      // Where the host acts on the window's last row anyway, it is left to the loop (the current window).
      bool host_acts =
          last >= options_.iterations || loop_.convergence().due(last) ||
          population_event_due(options_.population, loop_.population().schedule, last, options_.iterations);
      for (int k = 0; k < window_rows_ && !host_acts; ++k) {
        const double* r = window_.row(k);
        host_acts = r[kRingCandidates] > 0.0 || r[kRingNonFinite] != 0.0 || r[kRingSnapBad] != 0.0 ||
                    !std::isfinite(r[kRingForce]) || !std::isfinite(r[kRingKinetic]);
      }
      if (host_acts || stopping()) {
        ahead_window_ = true;
        return;
      }
      // The device's side of each iteration (take_row's and apply's without candidates); the loop's
      // side when the rule has gone on (take_held_row).
      for (int k = 0; k < window_rows_; ++k) {
        const double* r = window_.row(k);
        HeldRow h;
        std::copy(r, r + kRingSize, h.row.begin());
        h.entries = list_entries_;
        if (!boundary_nodes_.empty()) h.snap_arcs = 1 - cur_;
        held_.push_back(h);
        gm.update(r[kRingMaxForce]);
        skin_use_ = std::max({skin_use_, r[kRingSkin], r[kRingSnapSkin]});
        cur_ = 1 - cur_;
        ++since_build_;
        ++stats_.ahead_rows;
      }
      window_next_ = window_rows_;
      next = last + 1;
      if (stopping()) return;
      if (skin_use_ > skin_limit_ || options_.verlet_skin == 0.0) build_ahead(next);
    }
  } catch (...) {
    ahead_error_ = std::current_exception();
  }
}

template <typename Real>
void DeviceRun<Real>::build_ahead(int next) {
  // The build's saved state is made when the loop reaches it (remember_build_ahead); its boundary state
  // is the last held row's, read now (the device moves on), beside nodes_, which the measurement reads.
  if (!boundary_nodes_.empty()) {
    read(brec_, ahead_brec_, 4 * boundary_nodes_.size(), false);
    device_boundary_.read_arcs(held_.back().snap_arcs, ahead_arcs_, false);
    ++stats_.transfers;
    finish(ctx_.queue(), "boundary state ahead of a build");
  }
  const CommandCounts before = command_counts();
  rebuild(false);
  if (with_momentum()) {  // the carried moves it is saved with: a copy on the device
    ensure_size(ctx_, carried_build_, "momentum_at_build", 2 * n_);
    copy_buffer(ctx_.queue(), carried_.get(), carried_build_.get(), 2 * n_ * sizeof(Real),
                "copy of the carried moves at a build");
  }
  stats_.rebuild_commands = stats_.rebuild_commands + (command_counts() - before);
  if (stats_.rebuilds > 1) build_interval_ = since_build_;
  since_build_ = 0;
  ++ahead_builds_;
  ahead_build_at_ = next;
  ++stats_.ahead_rebuilds;
}

template <typename Real>
void DeviceRun<Real>::go_on_after_ahead() {
  join_ahead();
  // An error of the thread is the run's (still marked as ahead: whatever ends the run then, the state
  // is the check's, and nothing is read back from the device).
  if (ahead_error_) std::rethrow_exception(std::exchange(ahead_error_, nullptr));
  ahead_used_ = false;
  if (ahead_builds_ > 0 && saved_released_) {
    // The builds ahead replaced the build state the saved positions were freed against: the state
    // after the measurement's iteration (nodes_, read for it) is the saved state until the loop
    // reaches the last of them.
    std::optional<std::vector<Vec2>> momentum;
    if (with_momentum()) momentum = final_momentum();
    saved_released_ = false;
    std::vector<std::pair<std::size_t, Vec2>>().swap(saved_off_interior_);
    released_copy_ = NodeSet{};
    remember(std::move(momentum));
    saved_is_build_state_ = false;
  }
  // The run goes on past the check: its carried moves are no state of it any more.
  std::vector<Real>().swap(momentum_at_check_);
  check_momentum_saved_ = false;
  host_ahead_ = !held_.empty();  // else the device holds the state after loop_.done() (the current window's start)
}

template <typename Real>
void DeviceRun<Real>::take_held_row() {
  const HeldRow& h = held_[held_next_++];
  const double* r = h.row.data();
  row_dt_ = r[kRingDt];
  row_entries_ = h.entries;
  row_held_ = true;
  take_row_sums(r);
  if (h.snap_arcs >= 0) {
    boundary_stale_ = true;
    snap_arcs_ = h.snap_arcs;
  }
  candidates_.clear();
  moves_.clear();
  moves_finite_ = true;  // run_ahead holds no row with a move that is not finite
}

template <typename Real>
void DeviceRun<Real>::remember_build_ahead() {
  // loop_.done() is the iteration before the build: its boundary state as read then, its build state
  // and carried moves as the build left them on the device (no build since).
  if (!boundary_nodes_.empty()) restore_boundary(ahead_brec_, ahead_arcs_);
  std::vector<Real>().swap(ahead_brec_);
  std::vector<Real>().swap(ahead_arcs_);
  read(xy_build_, positions_host_[0], 2 * n_);
  read(q_build_, positions_host_[1], n_);
  std::optional<std::vector<Vec2>> momentum;
  if (with_momentum()) momentum = read_momentum(carried_build_);
  carried_build_ = Buffer<Real>();
  remember(std::move(momentum));
  saved_is_build_state_ = true;
  ahead_builds_ = 0;
}

template <typename Real>
void DeviceRun<Real>::check_row(int iteration, double dt_gm) {
  // The device's rule ran on a copy of the host's state: its dt must be the host's, bit for bit.
  const double device_dt = row_dt_;
  if (window_.device_rule() && device_dt != dt_gm)
    throw SimulationError(fmt::format("iteration {}: the device's global time step {} differs from the host's {}",
                                      iteration, device_dt, dt_gm));
  // Before the host moves anything: the last good state is still whole on the device.
  if (!std::isfinite(sum_force_) || !std::isfinite(sum_kinetic_) || !moves_finite_) {
    failed_at_ = last_good_state();
    throw non_finite_error(iteration, *failed_at_);
  }
}

template <typename Real>
IterationMoves DeviceRun<Real>::apply(int iteration) {
  IterationMoves out;
  if (row_held_) {
    // No candidates; the device's side (the buffers, the skin) was done ahead (run_ahead).
    out.boundary.clamped = snap_.clamped;
  } else {
    double skin_use = device_skin_use_;
    out.boundary = host_boundary(skin_use);
    cur_ = 1 - cur_;
    skin_use_ = std::max(skin_use_, skin_use);
  }
  if (out.boundary.snapped > 0) {
    // The rows are stale after a snap: the snapped node still holds its interior row (node_forces
    // does not filter a boundary node's row) and its new curve neighbours their old [prev, next].
    // The host reference rebuilds on any kind change (NeighbourCache), so the next step must too.
    if (skin_use_ <= skin_limit_) ++stats_.snap_rebuilds;
    skin_use_ = HUGE_VAL;
  }
  out.event = population_event(iteration);
  on_boundary_ += out.boundary.snapped;
  interior_ -= out.boundary.snapped;
  if (out.event) {
    on_boundary_ = nodes_.count(NodeKind::Boundary);
    interior_ = nodes_.count(NodeKind::Interior);
  }
  out.fixed = fixed_;
  out.on_boundary = on_boundary_;
  out.interior = interior_;
  return out;
}

template <typename Real>
void DeviceRun<Real>::after_row() {
  ++stats_.iterations;
  if (held_next_ >= held_.size()) {
    held_.clear();
    held_next_ = 0;
  }
  host_ahead_ = !held_.empty();  // the device ran past the held rows
  tangents_ahead_ = false;
}

// The stopping rule's measurement needs the nodes on the host. The device runs ahead while the host
// triangulates (run_ahead_): the rebuild the next iteration would start with, if one is due, then the
// next window, split after kAheadIterations (CPU devices). Its commands are the same, so the run is the
// same bit for bit; a run that stops here discards what it ran (after_iterations).
template <typename Real>
void DeviceRun<Real>::before_measure(int iteration, const GlobalTimeStep& gm) {
  read_back_nodes();
  if (run_ahead_ && iteration < options_.iterations && window_next_ >= window_rows_ &&
      !(options_.stop && options_.stop->load())) {
    rebuilt_ahead_ = rebuild_if_due(iteration + 1);
    check_momentum_saved_ = with_momentum() && rebuilt_ahead_;
    // Blocking: the state after this iteration stands in for the saved state during the check
    // (last_good_state), and needs its carried moves whole even when the device fails later.
    if (with_momentum() && !rebuilt_ahead_) read(carried_, momentum_at_check_, 2 * n_);
    host_ahead_ = true;  // a failure from here on falls back on the saved state: the device moves on
    if (overlap_ != MeasureOverlap::Off) {
      held_.clear();
      held_next_ = 0;
      ahead_builds_ = 0;
      ahead_stop_ = false;
      ahead_error_ = nullptr;
      pairs_examined_at_check_ = pairs_examined_;
      largest_row_at_check_ = largest_row_;
      ahead_used_ = true;
      release_saved_positions();
      ahead_thread_ = std::thread([this, first = iteration + 1, gm] { run_ahead(first, gm); });
      return;
    }
    begin_window(iteration + 1, gm, cpu_device_ ? kAheadIterations : window_.max_length());
    ++stats_.ahead_windows;
    release_saved_positions();
  }
}

template <typename Real>
void DeviceRun<Real>::after_observe() {
  // A build made before this iteration's measurement saved the state without it.
  if (rebuilt_ahead_) saved_state_.convergence = loop_.convergence().samples();
  rebuilt_ahead_ = false;
}

template <typename Real>
void DeviceRun<Real>::after_iterations() {
  if (ahead_used_) {
    // Stopped after a measurement the device ran ahead of (run_ahead): nodes_ and the boundary state
    // hold the state after loop_.done(); the iterations, rows and builds since are dropped, and so is
    // an error of theirs (past the stop).
    ahead_stop_ = true;
    join_ahead();
    ahead_used_ = false;
    ahead_error_ = nullptr;
    finish(ctx_.queue(), "iterations run ahead of a stop");
    held_.clear();
    held_next_ = 0;
    window_rows_ = window_next_ = 0;
    ahead_window_ = false;
    ahead_builds_ = 0;
    carried_build_ = Buffer<Real>();
    pairs_examined_ = pairs_examined_at_check_;
    largest_row_ = largest_row_at_check_;
  } else if (window_pending_) {
    // Stopped after a convergence check while the device ran ahead: nodes_ and the boundary state
    // hold the state after loop_.done() (read for the check); what the device ran since is dropped.
    finish(ctx_.queue(), "iterations run ahead of a stop");
    window_pending_ = false;
  } else {
    read_back_nodes();  // the final state
    momentum_at_check_.clear();
    check_momentum_saved_ = false;
  }
  // No step follows: the rows and the step's outputs go before end_run builds the final state beside
  // the measured mesh (they would set the peak of a converged run). The carried moves stay (end_run may
  // read them).
  stats_.device_bytes = device_bytes();
  neighbours_.release_rows();
  release_step_outputs();
  give_back_free_memory();
}

template <typename Real>
SimState DeviceRun<Real>::failure_state() {
  ahead_stop_ = true;
  join_ahead();
  if (!failed_at_) failed_at_ = last_good_state();
  return *failed_at_;
}

template <typename Real>
void DeviceRun<Real>::end_run(SimResult& result) {
  result.state = loop_.state(boundary_);
  if (with_momentum()) result.state.momentum = final_momentum();
  result.stats.pairs_examined += pairs_examined_;
  stats_.stride = largest_row_;
  const DeviceRunStats& d = stats_;
  result.stats.split = {{"device_step_seconds", d.step_seconds},
                        {"device_build_seconds", d.bin_seconds + d.gather_seconds},
                        {"device_host_test_seconds", d.host_seconds},
                        {"device_download_seconds", d.download_seconds},
                        {"device_upload_seconds", d.upload_seconds},
                        {"device_population_seconds", d.population_seconds},
                        {"device_population_transfer_seconds", d.population_transfer_seconds},
                        {"device_rebuilds", static_cast<double>(d.rebuilds)},
                        {"device_windows", static_cast<double>(d.windows)},
                        {"device_ahead_windows", static_cast<double>(d.ahead_windows)},
                        {"device_ahead_rows", static_cast<double>(d.ahead_rows)},
                        {"device_ahead_rebuilds", static_cast<double>(d.ahead_rebuilds)}};
}

template <typename Real>
std::size_t DeviceRun<Real>::device_bytes() const {
  return neighbours_.device_bytes() + partials_.bytes() + cand_index_.bytes() + cand_rec_.bytes() + brec_.bytes() +
         kind_.bytes() + budget_.bytes() + prev_.bytes() + next_.bytes() + bslot_.bytes() + bg_q_.bytes() +
         bg_root_.bytes() + bg_child_.bytes() + bg_corner_.bytes() + bg_cell_.bytes() + node_leaf_.bytes() +
         rec_.bytes() + rec_index_.bytes() + device_boundary_.bytes() + carried_.bytes() + carried_build_.bytes() +
         (6 + 5) * n_ * sizeof(Real);
}

SimResult run_device_resident(NodeSet& nodes, const GeometryTree& tree, const SpacingField& spacing,
                              const SimOptions& options, Context& ctx, StepProgram& program,
                              const SimCallbacks& callbacks, DeviceRunStats& stats) {
  stats = DeviceRunStats{};
  if (program.precision == Precision::Float)
    return DeviceRun<float>(nodes, tree, spacing, options, ctx, program, stats).run(callbacks);
  return DeviceRun<double>(nodes, tree, spacing, options, ctx, program, stats).run(callbacks);
}

}  // namespace pdmesh::ocl
