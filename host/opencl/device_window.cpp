// Host side of the windows of device-resident iterations; see device_window.hpp and kernels/window.cl.
#include "opencl/device_window.hpp"

#include <algorithm>

#include <fmt/format.h>

#include "opencl/device_boundary.hpp"

namespace pdmesh::ocl {

std::map<std::string, std::string> window_defines() {
  std::map<std::string, std::string> d;
  for (const auto& [name, slot] : {std::pair{"RING_FORCE", kRingForce},
                                   {"RING_KINETIC", kRingKinetic},
                                   {"RING_MOVING", kRingMoving},
                                   {"RING_WITHIN", kRingWithin},
                                   {"RING_COINCIDENT", kRingCoincident},
                                   {"RING_MAX_FORCE", kRingMaxForce},
                                   {"RING_SKIN", kRingSkin},
                                   {"RING_CLAMPED", kRingClamped},
                                   {"RING_SNAP_BAD", kRingSnapBad},
                                   {"RING_SNAP_SKIN", kRingSnapSkin},
                                   {"RING_DT", kRingDt},
                                   {"RING_CANDIDATES", kRingCandidates},
                                   {"RING_NON_FINITE", kRingNonFinite},
                                   {"RING_SIZE", kRingSize}})
    d.emplace(name, std::to_string(static_cast<int>(slot)));
  for (const auto& [name, slot] : {std::pair{"STATE_DT", kStateDt},
                                   {"STATE_PREVIOUS", kStatePrevious},
                                   {"STATE_HAS_PREVIOUS", kStateHasPrevious},
                                   {"STATE_DECREASES", kStateDecreases},
                                   {"STATE_INCREASES", kStateIncreases},
                                   {"STATE_SKIN", kStateSkin},
                                   {"STATE_SKIN_LIMIT", kStateSkinLimit}})
    d.emplace(name, std::to_string(static_cast<int>(slot)));
  d.emplace("COUNTER_CANDIDATES", std::to_string(static_cast<int>(kCounterCandidates)));
  d.emplace("COUNTER_NON_FINITE", std::to_string(static_cast<int>(kCounterNonFinite)));
  d.emplace("WINDOW_HALT", std::to_string(static_cast<int>(kWindowHalt)));
  d.emplace("WINDOW_ROWS", std::to_string(static_cast<int>(kWindowRows)));
  d.emplace("COUNTER_SNAP_DONE", std::to_string(static_cast<int>(kCounterSnapDone)));
  d.emplace("COUNTER_HOST", std::to_string(static_cast<int>(kCounterHost)));
  // The rule's constants as the shortest round-trip text, so that the kernel has the same doubles.
  d.emplace("GM_RUN_LENGTH", std::to_string(GlobalTimeStep::kRunLength));
  d.emplace("GM_GROW", fmt::format("{}", GlobalTimeStep::kGrow));
  d.emplace("GM_SHRINK", fmt::format("{}", GlobalTimeStep::kShrink));
  return d;
}

template <typename Real>
DeviceWindow<Real>::DeviceWindow(Context& ctx, bool device_rule)
    : ctx_(ctx), device_rule_(device_rule), dt2_(ctx, "step_dt2", 1), rows_(kRingSize * kWindowLength, 0.0) {
  if (device_rule_) {
    state_ = Buffer<double>(ctx, "time_step_rule_state", kStateSize);
    // The ring the host reads every window: host-visible memory where the device offers it.
    ring_ = Buffer<double>(ctx, "history_ring", kRingSize * kWindowLength, CL_MEM_READ_WRITE | CL_MEM_ALLOC_HOST_PTR);
  }
}

template <typename Real>
void DeviceWindow<Real>::begin(const GlobalTimeStep& gm, double skin_use, double skin_limit,
                               Buffer<std::int32_t>& counters) {
  transfers = bytes_up = bytes_down = 0;
  counters.upload(ctx_.queue(), zero_counters_, false);
  dt2_host_.assign(1, static_cast<Real>(gm.dt2()));
  dt2_.upload(ctx_.queue(), dt2_host_, false);
  transfers += 2;
  bytes_up += zero_counters_.size() * sizeof(std::int32_t) + sizeof(Real);
  if (!device_rule_) return;
  const GlobalTimeStep::State s = gm.state();
  state_host_.assign(kStateSize, 0.0);
  state_host_[kStateDt] = s.dt;
  state_host_[kStatePrevious] = s.previous ? *s.previous : 0.0;
  state_host_[kStateHasPrevious] = s.previous ? 1.0 : 0.0;
  state_host_[kStateDecreases] = s.consecutive_decreases;
  state_host_[kStateIncreases] = s.increases;
  state_host_[kStateSkin] = skin_use;
  state_host_[kStateSkinLimit] = skin_limit;
  state_.upload(ctx_.queue(), state_host_, false);
  ++transfers;
  bytes_up += state_host_.size() * sizeof(double);
}

template <typename Real>
void DeviceWindow<Real>::rule_args(ArgSetter& a, std::size_t groups, Buffer<Real>& partials) {
  if (!device_rule_) throw DeviceError("DeviceWindow::rule_args: the host runs the time-step rule");
  a(static_cast<cl_int>(groups))(partials)(state_)(ring_)(static_cast<cl_int>(kWindowLength))(dt2_);
}

template <typename Real>
void DeviceWindow<Real>::enqueue_rule(StepProgram& program, std::size_t groups, Buffer<Real>& partials,
                                      std::size_t snap_entries, Buffer<Real>& snap_partials,
                                      Buffer<std::int32_t>& counters) {
  if (!device_rule_) return;
  ArgSetter a(program.iteration_rule, "iteration_rule");
  a(static_cast<cl_int>(groups))(partials)(static_cast<cl_int>(snap_entries))(
      snap_partials)(counters)(state_)(ring_)(static_cast<cl_int>(kWindowLength))(dt2_);
  const std::size_t items = rule_by_group(program.force_loop) ? program.work_group : 1;
  launch(ctx_.queue(), program.iteration_rule, "iteration_rule", items, items);
}

template <typename Real>
void DeviceWindow<Real>::enqueue_reads(Context& ctx, std::size_t groups, Buffer<Real>& partials,
                                       std::size_t snap_entries, Buffer<Real>& snap_partials,
                                       Buffer<std::int32_t>& counters) {
  counters.download(ctx.queue(), counters_host_, kWindowCounters, false);
  transfers += 1;
  bytes_down += kWindowCounters * sizeof(std::int32_t);
  if (device_rule_) {
    ring_.download(ctx.queue(), rows_, rows_.size(), false);
    ++transfers;
    bytes_down += rows_.size() * sizeof(double);  // the whole ring: how many rows ran is known only after
  } else {
    // The host's sums of one iteration, in group order: what iteration_rule computes.
    partials.download(ctx.queue(), part_host_, kStepPartials * groups, false);
    if (snap_entries > 0) snap_partials.download(ctx.queue(), snap_host_, snap_entries, false);
    transfers += snap_entries > 0 ? 2 : 1;
    bytes_down += (kStepPartials * groups + snap_entries) * sizeof(Real);
  }
  flush(ctx.queue(), "device iterations");
}

template <typename Real>
int DeviceWindow<Real>::complete(Context& ctx, std::size_t groups, std::size_t snap_entries) {
  if (device_rule_) {
    finish(ctx.queue(), "device iterations");
    return counters_host_[kWindowRows];
  }
  finish(ctx.queue(), "device_step");
  double* r = rows_.data();
  std::fill(r, r + kRingSize, 0.0);
  for (std::size_t g = 0; g < groups; ++g) {
    const Real* p = part_host_.data() + kStepPartials * g;
    r[kRingForce] += static_cast<double>(p[0]);
    r[kRingKinetic] += static_cast<double>(p[1]);
    r[kRingMoving] += static_cast<double>(static_cast<std::size_t>(p[2]));
    r[kRingWithin] += static_cast<double>(static_cast<std::size_t>(p[3]));
    r[kRingCoincident] += static_cast<double>(static_cast<std::size_t>(p[4]));
    r[kRingMaxForce] = std::max(r[kRingMaxForce], static_cast<double>(p[5]));
    r[kRingSkin] = std::max(r[kRingSkin], static_cast<double>(p[6]));
  }
  const BoundarySnapResult snap = DeviceBoundary<Real>::sum(snap_host_, snap_entries);
  r[kRingClamped] = static_cast<double>(snap.clamped);
  r[kRingSnapBad] = static_cast<double>(snap.non_finite);
  r[kRingSnapSkin] = snap.skin_use;
  r[kRingDt] = 0.0;  // the host's rule
  r[kRingCandidates] = counters_host_[kCounterHost] != 0 ? counters_host_[kCounterCandidates] : 0;
  r[kRingNonFinite] = counters_host_[kCounterNonFinite];
  return 1;
}

template class DeviceWindow<float>;
template class DeviceWindow<double>;

}  // namespace pdmesh::ocl
