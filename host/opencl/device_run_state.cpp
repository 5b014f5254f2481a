// DeviceRun's transfers and saved state: the memory check, the node arrays up and back, the state
// saved at each build and the last good state after a failure, boundary synchronisation, and
// population events (the host's event between two uploads). The loop is in device_simulation.cpp.
#include "opencl/device_run.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <type_traits>

#include "core/errors.hpp"
#include "core/free_memory.hpp"
#include "core/parallel.hpp"
#include "sim/failure_report.hpp"
#include "sim/population_profile.hpp"
#include "spacing/background_field.hpp"

namespace pdmesh::ocl {

template <typename Real>
void DeviceRun<Real>::check_memory(std::uint64_t entries) const {
  const BackgroundFieldData& d = background_.data();
  const std::uint64_t field =
      4 * (d.root_node.size() + d.node_child.size() + d.leaf_corner.size() + d.leaf_cell.size()) +
      sizeof(Real) * d.corner_q.size();
  // The rows' entries as an average per node (the compact rows replace rows of one stride).
  const std::uint64_t per_node = n_ > 0 ? (entries + n_ - 1) / n_ : 0;
  check_device_memory(ctx_.device(), n_, nodes_.count(NodeKind::Boundary), field, sizeof(Real),
                      static_cast<int>(std::max<std::uint64_t>(per_node, kInitialStride)), with_momentum());
}

template <typename Real>
void DeviceRun<Real>::remember(std::optional<std::vector<Vec2>> momentum) {
  // Interior positions and every q as the build read them from the device (at the start: as uploaded,
  // nodes_'s); boundary nodes the host's. The host's skin test measures from them too.
  saved_nodes_ = nodes_;
  std::vector<Real>* v = positions_host_;
  if (!v[0].empty()) {
    for (std::size_t i = 0; i < n_; ++i) {
      if (saved_nodes_.kind[i] == NodeKind::Interior)
        saved_nodes_.x[i] = {static_cast<double>(v[0][2 * i]), static_cast<double>(v[0][2 * i + 1])};
      saved_nodes_.q[i] = static_cast<double>(v[1][i]);
    }
    // Read targets only (read after the build, blocking): not kept between builds.
    std::vector<Real>().swap(v[0]);
    std::vector<Real>().swap(v[1]);
  }
  saved_state_ = loop_.state(boundary_, false);
  // The tangents are zero but at the boundary nodes (a few in a thousand at a million nodes): kept as
  // those alone, bit for bit (a -0.0 is kept too), and expanded in last_good_state.
  std::vector<Vec2>& tangents = saved_state_.tangents;
  saved_tangent_count_ = tangents.size();
  saved_tangents_.clear();
  for (std::size_t i = 0; i < tangents.size(); ++i) {
    const Vec2 t = tangents[i];
    if (t.x != 0.0 || t.y != 0.0 || std::signbit(t.x) || std::signbit(t.y)) saved_tangents_.emplace_back(i, t);
  }
  std::vector<Vec2>().swap(tangents);
  // The device is not ahead here (a build or the start: no window is running), unless the carried
  // moves are given (a build run ahead of a measurement: its copy on the device).
  if (with_momentum()) saved_state_.momentum = momentum ? std::move(*momentum) : read_momentum();
  saved_rows_ = loop_.history().size();
}

// Puts the last good state into nodes_ and returns the driver state that goes with it: the state
// after iteration loop_.done() read back from the device, or, when the host is already ahead of it, the
// device cannot be read or what it holds is not finite, the state saved at the last build. With
// momentum always the saved state: a failed step has already overwritten the carried moves.
template <typename Real>
void DeviceRun<Real>::release_saved_positions() {
  if (!saved_is_build_state_ || saved_released_) return;
  if (check_restore_) released_copy_ = saved_nodes_;
  saved_off_interior_.clear();
  for (std::size_t i = 0; i < n_; ++i)
    if (saved_nodes_.kind[i] != NodeKind::Interior) saved_off_interior_.emplace_back(i, saved_nodes_.x[i]);
  std::vector<Vec2>().swap(saved_nodes_.x);
  std::vector<double>().swap(saved_nodes_.q);
  saved_released_ = true;
}

// Blocking: waits for what the device runs ahead (the next iteration's computation waits for it too).
template <typename Real>
void DeviceRun<Real>::restore_saved_positions() {
  if (!saved_released_) return;
  {
    std::vector<Real> xy, q;
    xy_build_.download(ctx_.queue(), xy, 2 * n_);
    q_build_.download(ctx_.queue(), q, n_);
    saved_nodes_.x.resize(n_);
    saved_nodes_.q.resize(n_);
    for (std::size_t i = 0; i < n_; ++i) {
      saved_nodes_.x[i] = {static_cast<double>(xy[2 * i]), static_cast<double>(xy[2 * i + 1])};
      saved_nodes_.q[i] = static_cast<double>(q[i]);
    }
  }
  for (const auto& [i, p] : saved_off_interior_) saved_nodes_.x[i] = p;
  std::vector<std::pair<std::size_t, Vec2>>().swap(saved_off_interior_);
  saved_released_ = false;
  ++stats_.saved_restores;
  if (check_restore_) {
    for (std::size_t i = 0; i < n_; ++i)
      if (std::memcmp(&saved_nodes_.x[i], &released_copy_.x[i], sizeof(Vec2)) != 0 ||
          std::memcmp(&saved_nodes_.q[i], &released_copy_.q[i], sizeof(double)) != 0)
        throw SimulationError(fmt::format("node {}: the saved state read back from the device differs", i));
    released_copy_ = NodeSet{};
  }
}

template <typename Real>
SimState DeviceRun<Real>::last_good_state() {
  if (saved_released_) {
    // During a convergence check the device runs ahead of: the host holds the state after
    // loop_.done() whole (nodes_ and the boundary read for the check; the carried moves read before
    // the device went ahead, final_momentum), newer than the saved one.
    SimState state = loop_.state(boundary_);
    if (with_momentum()) state.momentum = final_momentum();
    return state;
  }
  if (!host_ahead_ && !tangents_ahead_ && !with_momentum()) {
    try {
      std::vector<Real> x, y, q;
      download_positions(cur_, x, y);
      q_[cur_].download(ctx_.queue(), q, n_);
      bool finite = true;
      for (std::size_t i = 0; i < n_; ++i)
        finite = finite && std::isfinite(static_cast<double>(x[i])) && std::isfinite(static_cast<double>(y[i])) &&
                 q[i] > 0 && std::isfinite(static_cast<double>(q[i]));
      if (finite) {
        if (boundary_stale_) sync_boundary_from(cur_);
        for (std::size_t i = 0; i < n_; ++i) {
          if (nodes_.kind[i] == NodeKind::Interior)
            nodes_.x[i] = {static_cast<double>(x[i]), static_cast<double>(y[i])};
          nodes_.q[i] = static_cast<double>(q[i]);
        }
        return loop_.state(boundary_);
      }
    } catch (const Error&) {
      // The device cannot be read: the saved state below.
    }
  }
  nodes_ = saved_nodes_;
  SimState state = saved_state_;
  state.tangents.assign(saved_tangent_count_, Vec2{});
  for (const auto& [i, t] : saved_tangents_) state.tangents[i] = t;
  const std::vector<HistoryRow>& history = loop_.history();
  state.history.assign(history.begin(), history.begin() + static_cast<std::ptrdiff_t>(saved_rows_));
  return state;
}

// The device's new positions (xy_[1 - cur_]) name the first node whose move was not finite; its
// neighbourhood is described at the last good positions (nodes_ holds them).
template <typename Real>
SimulationError DeviceRun<Real>::non_finite_error(int iteration, const SimState& good) {
  std::size_t bad = n_;
  try {
    std::vector<Real> x, y;
    download_positions(1 - cur_, x, y);
    for (std::size_t i = 0; i < n_ && bad == n_; ++i)
      if (!std::isfinite(static_cast<double>(x[i])) || !std::isfinite(static_cast<double>(y[i]))) bad = i;
  } catch (const Error&) {
  }
  const std::string sums = fmt::format("sum |F| {}, sum kinetic {}", sum_force_, sum_kinetic_);
  if (bad == n_)
    return SimulationError(
        fmt::format("iteration {}: non-finite force sums ({}); no node's new position is "
                    "non-finite (last good state: after iteration {})",
                    iteration, sums, good.iterations_done));
  return SimulationError(
      fmt::format("iteration {}: non-finite force or move ({}) on {} (positions after iteration {})", iteration, sums,
                  describe_neighbourhood(nodes_, bad, options_.cutoff * nodes_.q[bad]), good.iterations_done));
}

// The state after the last complete iteration into nodes_: interior positions and every q from the
// device, the boundary state when the host's is older (sync_boundary). Not counted as per-iteration traffic.
template <typename Real>
void DeviceRun<Real>::read_back_nodes() {
  std::vector<Real> x, y, q;
  const std::uint64_t down = stats_.bytes_down, transfers = stats_.transfers;
  if (boundary_stale_) sync_boundary();
  read_positions(cur_, x, y);
  read(q_[cur_], q, n_);
  stats_.bytes_down = down;
  stats_.transfers = transfers;
  for (std::size_t i = 0; i < n_; ++i) {
    if (nodes_.kind[i] == NodeKind::Interior) nodes_.x[i] = {static_cast<double>(x[i]), static_cast<double>(y[i])};
    nodes_.q[i] = static_cast<double>(q[i]);
  }
}

template <typename Real>
void DeviceRun<Real>::upload_initial() {
  const BackgroundFieldData& d = background_.data();
  // The host keeps the field for the whole run (background_): a CPU device reads its arrays in place,
  // another gets a copy.
  const auto field = [&](const char* name, const auto& host) {
    using T = typename std::decay_t<decltype(host)>::value_type;
    if (cpu_device_) return Buffer<T>::over_host(ctx_, name, host);
    Buffer<T> b(ctx_, name, host.size());
    write(b, host);
    return b;
  };
  bg_root_ = field("bg_root_node", d.root_node);
  bg_child_ = field("bg_node_child", d.node_child);
  bg_corner_ = field("bg_leaf_corner", d.leaf_corner);
  bg_cell_ = field("bg_leaf_cell", d.leaf_cell);
  if constexpr (std::is_same_v<Real, double>) {
    bg_q_ = field("bg_corner_q", d.corner_q);
  } else {
    bg_q_ = Buffer<Real>(ctx_, "bg_corner_q", d.corner_q.size());
    write(bg_q_, to_real<Real>(d.corner_q));
  }
  counters_ = Buffer<std::int32_t>(ctx_, "step_counters", kWindowCounters);  // device_window.hpp, WindowCounter
  device_boundary_.upload_curves();
  upload_nodes(nullptr, nullptr);
  if (with_momentum() && options_.resume && !options_.resume->momentum.empty()) {
    MomentumState carried;
    momentum_from_state(options_.resume->momentum, n_, carried);
    write(carried_, interleave(carried.px, carried.py));
  }
}

template <typename Real>
std::vector<Vec2> DeviceRun<Real>::read_momentum(Buffer<Real>& carried) {
  std::vector<Real> xy;
  carried.download(ctx_.queue(), xy, 2 * n_);
  std::vector<Vec2> out(n_);
  for (std::size_t i = 0; i < n_; ++i) out[i] = {static_cast<double>(xy[2 * i]), static_cast<double>(xy[2 * i + 1])};
  return out;
}

template <typename Real>
std::vector<Vec2> DeviceRun<Real>::final_momentum() {
  // The device ran ahead of a check just after a build: remember() read the same carried moves.
  if (check_momentum_saved_) return saved_state_.momentum;
  if (momentum_at_check_.empty()) return read_momentum();
  // The carried moves after loop_.done(), read before the device ran ahead.
  std::vector<Vec2> momentum(n_);
  for (std::size_t i = 0; i < n_; ++i)
    momentum[i] = {static_cast<double>(momentum_at_check_[2 * i]), static_cast<double>(momentum_at_check_[2 * i + 1])};
  return momentum;
}

template <typename Real>
void DeviceRun<Real>::reset_momentum(const std::vector<std::int32_t>& nodes) {
  std::vector<Real> xy;
  read(carried_, xy, 2 * n_);
  for (std::int32_t i : nodes) xy[2 * static_cast<std::size_t>(i)] = xy[2 * static_cast<std::size_t>(i) + 1] = Real(0);
  write(carried_, xy);
}

template <typename Real>
void DeviceRun<Real>::upload_nodes(const std::vector<double>* budgets, const std::vector<std::int32_t>* leaves) {
  const std::size_t n = n_;
  saved_is_build_state_ = false;  // xy_build_ and q_build_ hold nothing until the next build
  // Every node buffer is made again below: the old ones go first (a population event's re-upload).
  for (auto* b : {&xy_[0], &xy_[1], &q_[0], &q_[1], &tx_, &ty_, &q_build_, &xy_build_, &budget_, &cand_rec_, &partials_,
                  &carried_})
    *b = Buffer<Real>();
  cand_index_ = Buffer<std::int32_t>();
  node_leaf_ = Buffer<std::int32_t>();
  std::vector<double> x(n), y(n), tx(n), ty(n), budget(n, 0.0);
  for (std::size_t i = 0; i < n; ++i) {
    x[i] = nodes_.x[i].x;
    y[i] = nodes_.x[i].y;
    const Vec2 t = boundary_.tangent(static_cast<int>(i));
    tx[i] = t.x;
    ty[i] = t.y;
  }
  if (budgets) {
    budget = *budgets;
  } else {
    // Clearance budgets of the interior nodes (exact test once, as the host reference's first
    // iteration): a point-in-domain test and a closest-segment search each, ~10 ms for 14k nodes on one
    // core at the start of the run, so on every core.
    parallel_for(
        n,
        [&](std::size_t i) {
          if (nodes_.kind[i] == NodeKind::Interior && boundary_.tree().inside(nodes_.x[i]))
            budget[i] = device_budget(nodes_.x[i], boundary_.clearance_from(nodes_.x[i]));
        },
        2048);
  }
  cur_ = 0;
  xy_[0] = Buffer<Real>(ctx_, "xy", 2 * n);
  q_[0] = Buffer<Real>(ctx_, "q", n);
  for (auto* b : {&tx_, &ty_, &q_build_}) *b = Buffer<Real>(ctx_, "node_array", n);
  xy_build_ = Buffer<Real>(ctx_, "xy_build", 2 * n);
  budget_ = Buffer<Real>(ctx_, "clearance_budget", n);
  write(xy_[0], interleave(x, y));
  write(q_[0], to_real<Real>(nodes_.q));
  write(tx_, to_real<Real>(tx));
  write(ty_, to_real<Real>(ty));
  write(budget_, to_real<Real>(budget));
  allocate_step_outputs();
  partials_ = Buffer<Real>(ctx_, "partials", kStepPartials * groups());
  // Each node's leaf: the guess the step kernel tests before descending.
  std::vector<std::int32_t> leaf(n);
  if (leaves) {
    leaf = *leaves;
  } else {
    parallel_for(
        n,
        [&](std::size_t i) {
          double u, v;
          leaf[i] = background_locate(background_.data(), nodes_.x[i], u, v);
        },
        4096);
  }
  node_leaf_ = Buffer<std::int32_t>(ctx_, "node_leaf", n);
  write(node_leaf_, leaf);
  // The carried moves start at zero, also after a population event changed the node set (the
  // resumed ones: upload_initial). Without momentum the step kernel never reads its buffer.
  carried_ = Buffer<Real>(ctx_, "momentum", with_momentum() ? 2 * n : 2);
  write(carried_, std::vector<Real>(with_momentum() ? 2 * n : 2, Real(0)));
  kind_host_.resize(n);
  upload_topology();
}

template <typename Real>
void DeviceRun<Real>::release_step_outputs() {
  xy_[1 - cur_] = Buffer<Real>();
  q_[1 - cur_] = Buffer<Real>();
  cand_index_ = Buffer<std::int32_t>();
  cand_rec_ = Buffer<Real>();
}

template <typename Real>
void DeviceRun<Real>::allocate_step_outputs() {
  xy_[1 - cur_] = Buffer<Real>(ctx_, "xy", 2 * n_);
  q_[1 - cur_] = Buffer<Real>(ctx_, "q", n_);
  cand_index_ = Buffer<std::int32_t>(ctx_, "cand_index", n_);
  cand_rec_ = Buffer<Real>(ctx_, "cand_rec", 4 * n_);
}

// Population control on the device run: the whole state comes back (interior positions and every q
// from the device; boundary positions are the host's), the event runs on the host exactly as in the
// host reference, and when it changed the node set the node arrays go up again (kept nodes keep their
// budgets and leaves) and the lists are rebuilt before the next step.
template <typename Real>
std::optional<PopulationCounts> DeviceRun<Real>::population_event(int iteration) {
  if (!population_event_due(options_.population, loop_.population().schedule, iteration, options_.iterations))
    return std::nullopt;
  const auto t0 = Clock::now();
  if (boundary_stale_) sync_boundary();
  // The step's outputs and candidate records are rewritten by the next step before they are read:
  // they are freed while the host's event runs (its triangulation sets the run's peak) and made again
  // after it, by upload_nodes when the node set changed. So are the neighbour rows and grids: the
  // lists are built again before the next step, also when the event changed nothing (the forces
  // filter every row by the cut-off and rows are sorted by node index, so a build at another
  // iteration gives the same forces).
  release_step_outputs();
  neighbours_.release_rows();
  skin_use_ = HUGE_VAL;
  // The event triangulates the nodes: without the free pages of the builds before it.
  give_back_free_memory();
  population_profile::add("release", since(t0));
  const auto t_read = Clock::now();
  std::vector<std::int32_t> leaves;
  std::vector<double> budgets;
  {  // The read targets are freed before the event's own arrays are made.
    std::vector<Real> x, y, q, budget;
    read_positions(cur_, x, y);
    for (auto [from, to] : {std::pair{&q_[cur_], &q}, {&budget_, &budget}}) read(*from, *to, n_);
    read(node_leaf_, leaves, n_);
    stats_.population_transfer_seconds += since(t0);
    for (std::size_t i = 0; i < n_; ++i) {
      if (nodes_.kind[i] == NodeKind::Interior) nodes_.x[i] = {static_cast<double>(x[i]), static_cast<double>(y[i])};
      nodes_.q[i] = static_cast<double>(q[i]);
    }
    budgets.assign(budget.begin(), budget.end());
  }
  population_profile::add("read back", since(t_read));
  std::vector<int> old_of_new;
  const std::size_t old_n = n_;
  const auto counts = device_population_event(loop_.population(), options_.population, iteration, options_.iterations,
                                              nodes_, boundary_, background_, budgets, leaves, &old_of_new);
  if (counts && counts->changed()) {
    n_ = nodes_.size();
    // The next build lays its rows out from the last build's counts, renumbered (no counting pass).
    neighbours_.carry_counts(old_of_new, old_n);
    const auto t1 = Clock::now();
    upload_nodes(&budgets, &leaves);
    finish(ctx_.queue(), "population re-upload");
    stats_.population_transfer_seconds += since(t1);
    population_profile::add("re-upload", since(t1));
  } else {
    allocate_step_outputs();
  }
  stats_.population_seconds += since(t0);
  population_profile::add("device event", since(t0));
  population_profile::print(fmt::format("after iteration {}", iteration).c_str());
  return counts;
}

template <typename Real>
void DeviceRun<Real>::upload_topology() {
  const std::size_t n = n_;
  std::vector<int> prev, next;
  boundary_.curve_neighbours(nodes_, prev, next);
  std::vector<std::int32_t> bslot(n, -1);
  const std::uint64_t before = command_counts().writes;
  boundary_nodes_ = device_boundary_.upload_topology(nodes_, boundary_.arcs());
  stats_.transfers += command_counts().writes - before;
  for (std::size_t s = 0; s < boundary_nodes_.size(); ++s)
    bslot[static_cast<std::size_t>(boundary_nodes_[s])] = static_cast<std::int32_t>(s);
  for (std::size_t i = 0; i < n; ++i) kind_host_[i] = static_cast<std::uint8_t>(nodes_.kind[i]);
  ensure_size(ctx_, kind_, "kind", n);
  ensure_size(ctx_, prev_, "prev", n);
  ensure_size(ctx_, next_, "next", n);
  ensure_size(ctx_, bslot_, "bslot", n);
  ensure_size(ctx_, brec_, "brec", 4 * boundary_nodes_.size());
  write(kind_, kind_host_);
  write(prev_, std::vector<std::int32_t>(prev.begin(), prev.end()));
  write(next_, std::vector<std::int32_t>(next.begin(), next.end()));
  write(bslot_, bslot);
}

template <typename Real>
void DeviceRun<Real>::boundary_positions_on_curves() {
  if constexpr (!std::is_same_v<Real, double>) {
    const std::vector<Curve>& curves = boundary_.tree().geometry().curves;
    for (std::size_t c = 0; c < curves.size(); ++c) {
      const std::vector<int>& list = nodes_.curve_nodes[c];
      const std::vector<double>& arcs = boundary_.arcs()[c];
      for (std::size_t k = 1; k + 1 < list.size(); ++k) {
        const auto i = static_cast<std::size_t>(list[k]);
        if (nodes_.kind[i] == NodeKind::Boundary)
          nodes_.x[i] = closest_on_curve_range(curves[c], nodes_.x[i], arcs[k], arcs[k]).p;
      }
    }
  }
}

template <typename Real>
void DeviceRun<Real>::sync_boundary() {
  // The records are the last boundary_snap's for the current slots: the slots change only in
  // upload_topology, which runs with the host's boundary state current (synced first).
  std::vector<Real>& rec = brec_host_;
  read(brec_, rec, 4 * boundary_nodes_.size(), false);
  device_boundary_.read_arcs(snap_arcs_, arcs_host_, false);
  ++stats_.transfers;
  finish(ctx_.queue(), "boundary state");
  stats_.bytes_down += arcs_host_.size() * sizeof(Real);
  restore_boundary(rec, arcs_host_);
}

template <typename Real>
void DeviceRun<Real>::restore_boundary(const std::vector<Real>& rec, const std::vector<Real>& flat_arcs) {
  std::vector<std::vector<double>> arcs = DeviceBoundary<Real>::unflatten(flat_arcs, nodes_);
  std::vector<Vec2> tangents = boundary_.tangents();
  for (std::size_t s = 0; s < boundary_nodes_.size(); ++s) {
    const auto i = static_cast<std::size_t>(boundary_nodes_[s]);
    nodes_.x[i] = {static_cast<double>(rec[4 * s]), static_cast<double>(rec[4 * s + 1])};
    tangents[i] = {static_cast<double>(rec[4 * s + 2]), static_cast<double>(rec[4 * s + 3])};
  }
  boundary_.restore(nodes_, std::move(arcs), std::move(tangents));
  boundary_positions_on_curves();
  boundary_stale_ = false;
}

template <typename Real>
void DeviceRun<Real>::sync_boundary_from(int which) {
  std::vector<Real> x, y, tx, ty;
  read_positions(which, x, y);
  read(tx_, tx, n_);
  read(ty_, ty, n_);
  std::vector<std::vector<double>> arcs = device_boundary_.download_arcs(which, nodes_);
  ++stats_.transfers;
  stats_.bytes_down += device_boundary_.arc_entries() * sizeof(Real);
  std::vector<Vec2> tangents(n_);
  for (std::size_t i = 0; i < n_; ++i) {
    if (nodes_.kind[i] != NodeKind::Boundary) continue;
    nodes_.x[i] = {static_cast<double>(x[i]), static_cast<double>(y[i])};
    tangents[i] = {static_cast<double>(tx[i]), static_cast<double>(ty[i])};
  }
  boundary_.restore(nodes_, std::move(arcs), std::move(tangents));
  boundary_positions_on_curves();
  boundary_stale_ = false;
}

// The members above in both precisions (device_simulation.cpp instantiates its own by using them):
// an explicit instantiation defines only the members defined before it ([temp.explicit]).
template class DeviceRun<float>;
template class DeviceRun<double>;

}  // namespace pdmesh::ocl
