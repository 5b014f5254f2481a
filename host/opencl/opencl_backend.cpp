// The OpenCL StepBackend; see opencl_backend.hpp. Float results are widened to double on download.
#include "opencl/opencl_backend.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "core/errors.hpp"
#include "sim/reference/metric_neighbour_cache.hpp"
#include "sim/reference/reference_backend.hpp"
#include "opencl/device_neighbours.hpp"
#include "opencl/step_program.hpp"

namespace pdmesh::ocl {
namespace {

template <typename Real>
class OpenclBackend final : public StepBackend {
 public:
  OpenclBackend(Context& ctx, Precision precision, ForceLoop loop)
      : ctx_(ctx), program_(ctx, precision, loop), neighbours_(ctx, program_) {}

  std::string name() const override {
    return fmt::format("opencl:{}:{} ({}, {})", ctx_.device().platform, ctx_.device().device, ctx_.device().name,
                       std::is_same_v<Real, double> ? "double" : "float");
  }

  void build_neighbours(const SimParticles& p, double cutoff, NeighbourList& list, NeighbourFlags& flags) override {
    if (p.has_metric()) {
      // Metric mode: the exact list of the host reference (the contract's rows), through its Verlet
      // candidates; the device's multi-level binning has no elliptic search yet.
      metric_rows_.build(p, cutoff, list, flags);
      return;
    }
    upload_particles(p);
    const std::size_t n = p.size();
    const int stride = std::max(list.stride, 2);
    flags = neighbours_.build(n, cutoff, xy_, q_, kind_, prev_, next_);
    list.stride = stride;
    const auto s = static_cast<std::size_t>(stride);
    list.count.assign(n, 0);
    list.index.assign(n * s, -1);
    if (flags.first_invalid >= 0) {
      // As the reference: boundary rows only.
      for (std::size_t i = 0; i < n; ++i)
        if (p.kind[i] == kSimBoundary) {
          list.count[i] = 2;
          list.index[i * s] = p.prev[i];
          list.index[i * s + 1] = p.next[i];
        }
      flags.max_count = std::count(p.kind.begin(), p.kind.end(), kSimBoundary) > 0 ? 2 : 0;
      return;
    }
    // The compact rows into the StepBackend's padded ones: a row longer than the stride keeps its
    // first `stride` entries, the smallest indices (rows are sorted), as the reference's truncated row.
    std::vector<std::uint64_t> offset;
    std::vector<std::int32_t> entries;
    neighbours_.count().download(ctx_.queue(), list.count, n);
    neighbours_.offset().download(ctx_.queue(), offset, n + 1);
    neighbours_.index().download(ctx_.queue(), entries);  // whole: moved rows lie behind offset[n]
    for (std::size_t i = 0; i < n; ++i) {
      const std::size_t listed = std::min<std::size_t>(static_cast<std::size_t>(list.count[i]), s);
      std::copy_n(entries.begin() + static_cast<std::ptrdiff_t>(offset[i]), listed,
                  list.index.begin() + static_cast<std::ptrdiff_t>(i * s));
    }
    flags.overflow = flags.max_count > stride ? 1U : 0U;
  }

  void compute_forces(const SimParticles& p, const NeighbourList& list, const ForceParams& params,
                      ForceResult& out) override {
    if (p.has_metric()) {
      compute_forces_metric(p, list, params, out);
      return;
    }
    upload_particles(p);
    const std::size_t n = p.size();
    ensure_size(ctx_, count_, "count", n);
    ensure_size(ctx_, index_, "index", list.index.size());
    count_.upload(ctx_.queue(), list.count);
    index_.upload(ctx_.queue(), list.index);
    ensure_size(ctx_, fx_, "fx", n);
    ensure_size(ctx_, fy_, "fy", n);
    ensure_size(ctx_, r0_, "r0", n);
    ensure_size(ctx_, coincident_, "coincident", n);
    ensure_size(ctx_, limit_, "dt2_limit", n);
    ArgSetter args(program_.compute_forces, "compute_forces");
    args(static_cast<cl_int>(n))(static_cast<cl_int>(list.stride))(static_cast<Real>(params.lj_a))(
        static_cast<cl_int>(params.r0_any_direction ? 1 : 0))(static_cast<Real>(params.stability_factor))(
        xy_)(q_)(kind_)(tx_)(ty_)(count_)(index_)(fx_)(fy_)(r0_)(limit_)(coincident_);
    launch(ctx_.queue(), program_.compute_forces, "compute_forces", n, program_.work_group);
    out.fx = download(fx_, n);
    out.fy = download(fy_, n);
    out.r0 = download(r0_, n);
    if (params.stability_factor > 0.0) {
      out.dt2_limit = download(limit_, n);
      // Fixed nodes keep the reference's HUGE_VAL (the kernel skips them).
      for (std::size_t i = 0; i < n; ++i)
        if (p.kind[i] == kSimFixed) out.dt2_limit[i] = HUGE_VAL;
    } else {
      out.dt2_limit.clear();
    }
    std::vector<std::int32_t> c;
    coincident_.download(ctx_.queue(), c, n);
    out.coincident_pairs = 0;
    for (auto v : c) out.coincident_pairs += static_cast<std::uint64_t>(v);
  }

  void time_step_and_move(const SimParticles& p, const ForceResult& forces, double dt_gm2, MoveResult& out) override {
    if (p.has_metric()) {
      time_step_and_move_metric(p, forces, dt_gm2, out);
      return;
    }
    const std::size_t n = p.size();
    upload_forces(p, forces);
    ensure_size(ctx_, r0_, "r0", n);
    r0_.upload(ctx_.queue(), to_real<Real>(forces.r0));
    const bool has_limit = !forces.dt2_limit.empty();
    ensure_size(ctx_, limit_, "dt2_limit", n);
    if (has_limit) limit_.upload(ctx_.queue(), to_real<Real>(forces.dt2_limit));
    ensure_size(ctx_, dx_, "dx", n);
    ensure_size(ctx_, dy_, "dy", n);
    ensure_size(ctx_, dt2_, "dt2", n);
    ArgSetter args(program_.time_step_and_move, "time_step_and_move");
    args(static_cast<cl_int>(n))(static_cast<Real>(dt_gm2))(static_cast<cl_int>(has_limit ? 1 : 0))(
        kind_)(fx_)(fy_)(r0_)(limit_)(dx_)(dy_)(dt2_);
    launch(ctx_.queue(), program_.time_step_and_move, "time_step_and_move", n, program_.work_group);
    out.dx = download(dx_, n);
    out.dy = download(dy_, n);
    out.dt2 = download(dt2_, n);
  }

  void apply_momentum(const SimParticles& p, const ForceResult& forces, double beta, double mix, MoveResult& moves,
                      MomentumState& carried) override {
    if (p.has_metric()) {
      apply_momentum_metric(p, forces, beta, mix, moves, carried);
      return;
    }
    const std::size_t n = p.size();
    carried.px.resize(n, 0.0);
    carried.py.resize(n, 0.0);
    upload_forces(p, forces);
    ensure_size(ctx_, r0_, "r0", n);
    r0_.upload(ctx_.queue(), to_real<Real>(forces.r0));
    ensure_size(ctx_, dx_, "dx", n);
    ensure_size(ctx_, dy_, "dy", n);
    ensure_size(ctx_, carried_, "momentum", 2 * n);
    dx_.upload(ctx_.queue(), to_real<Real>(moves.dx));
    dy_.upload(ctx_.queue(), to_real<Real>(moves.dy));
    std::vector<Real> pxy(2 * n);  // the device run's layout: x and y interleaved
    for (std::size_t i = 0; i < n; ++i) {
      pxy[2 * i] = static_cast<Real>(carried.px[i]);
      pxy[2 * i + 1] = static_cast<Real>(carried.py[i]);
    }
    carried_.upload(ctx_.queue(), pxy);
    ArgSetter args(program_.apply_momentum, "apply_momentum");
    args(static_cast<cl_int>(n))(static_cast<Real>(beta))(static_cast<Real>(mix))(
        kind_)(fx_)(fy_)(r0_)(dx_)(dy_)(carried_);
    launch(ctx_.queue(), program_.apply_momentum, "apply_momentum", n, program_.work_group);
    moves.dx = download(dx_, n);
    moves.dy = download(dy_, n);
    const std::vector<double> out = download(carried_, 2 * n);
    for (std::size_t i = 0; i < n; ++i) {
      carried.px[i] = out[2 * i];
      carried.py[i] = out[2 * i + 1];
    }
  }

  StepSums reduce(const SimParticles& p, const ForceResult& forces, const MoveResult& moves) override {
    if (p.has_metric()) return reduce_metric(p, forces, moves);
    const std::size_t n = p.size();
    upload_forces(p, forces);
    ensure_size(ctx_, dt2_, "dt2", n);
    dt2_.upload(ctx_.queue(), to_real<Real>(moves.dt2));
    const std::size_t groups = (n + program_.work_group - 1) / program_.work_group;
    ensure_size(ctx_, partials_, "partials", 4 * groups);
    ArgSetter args(program_.reduce, "reduce");
    args(static_cast<cl_int>(n))(kind_)(fx_)(fy_)(dt2_)(partials_);
    launch(ctx_.queue(), program_.reduce, "reduce", n, program_.work_group);
    const std::vector<double> part = download(partials_, 4 * groups);
    StepSums s;
    for (std::size_t g = 0; g < groups; ++g) {
      s.sum_force += part[4 * g];
      s.sum_kinetic += part[4 * g + 1];
      s.moving += static_cast<std::size_t>(part[4 * g + 2]);
      s.max_force = std::max(s.max_force, part[4 * g + 3]);
    }
    return s;
  }

 private:
  // Metric mode (kernels/metric.cl; the reference's forces_metric.cpp and time_step.cpp).
  void compute_forces_metric(const SimParticles& p, const NeighbourList& list, const ForceParams& params,
                             ForceResult& out) {
    upload_particles(p);
    upload_metric(p);
    const std::size_t n = p.size();
    ensure_size(ctx_, count_, "count", n);
    ensure_size(ctx_, index_, "index", list.index.size());
    count_.upload(ctx_.queue(), list.count);
    index_.upload(ctx_.queue(), list.index);
    ensure_size(ctx_, fx_, "fx", n);
    ensure_size(ctx_, fy_, "fy", n);
    ensure_size(ctx_, r0_, "r0", n);
    ensure_size(ctx_, coincident_, "coincident", n);
    ensure_size(ctx_, limit_, "dt2_limit", n);
    ArgSetter args(program_.compute_forces_metric, "compute_forces_metric");
    args(static_cast<cl_int>(n))(static_cast<cl_int>(list.stride))(static_cast<Real>(params.lj_a))(
        static_cast<cl_int>(params.r0_any_direction ? 1 : 0))(static_cast<Real>(params.stability_factor))(
        xy_)(m11_)(m12_)(m22_)(kind_)(tx_)(ty_)(count_)(index_)(fx_)(fy_)(r0_)(limit_)(coincident_);
    launch(ctx_.queue(), program_.compute_forces_metric, "compute_forces_metric", n, program_.work_group);
    out.fx = download(fx_, n);
    out.fy = download(fy_, n);
    out.r0 = download(r0_, n);
    if (params.stability_factor > 0.0)
      out.dt2_limit = download(limit_, n);  // Fixed nodes: INFINITY, the reference's HUGE_VAL
    else
      out.dt2_limit.clear();
    std::vector<std::int32_t> c;
    coincident_.download(ctx_.queue(), c, n);
    out.coincident_pairs = 0;
    for (auto v : c) out.coincident_pairs += static_cast<std::uint64_t>(v);
  }

  void time_step_and_move_metric(const SimParticles& p, const ForceResult& forces, double dt_gm2, MoveResult& out) {
    const std::size_t n = p.size();
    upload_forces(p, forces);
    upload_metric(p);
    ensure_size(ctx_, r0_, "r0", n);
    r0_.upload(ctx_.queue(), to_real<Real>(forces.r0));
    const bool has_limit = !forces.dt2_limit.empty();
    ensure_size(ctx_, limit_, "dt2_limit", n);
    if (has_limit) limit_.upload(ctx_.queue(), to_real<Real>(forces.dt2_limit));
    ensure_size(ctx_, dx_, "dx", n);
    ensure_size(ctx_, dy_, "dy", n);
    ensure_size(ctx_, dt2_, "dt2", n);
    ArgSetter args(program_.time_step_and_move_metric, "time_step_and_move_metric");
    args(static_cast<cl_int>(n))(static_cast<Real>(dt_gm2))(static_cast<cl_int>(has_limit ? 1 : 0))(
        kind_)(fx_)(fy_)(r0_)(limit_)(m11_)(m12_)(m22_)(dx_)(dy_)(dt2_);
    launch(ctx_.queue(), program_.time_step_and_move_metric, "time_step_and_move_metric", n, program_.work_group);
    out.dx = download(dx_, n);
    out.dy = download(dy_, n);
    out.dt2 = download(dt2_, n);
  }

  void apply_momentum_metric(const SimParticles& p, const ForceResult& forces, double beta, double mix,
                             MoveResult& moves, MomentumState& carried) {
    const std::size_t n = p.size();
    carried.px.resize(n, 0.0);
    carried.py.resize(n, 0.0);
    upload_forces(p, forces);
    upload_metric(p);
    ensure_size(ctx_, r0_, "r0", n);
    r0_.upload(ctx_.queue(), to_real<Real>(forces.r0));
    ensure_size(ctx_, dx_, "dx", n);
    ensure_size(ctx_, dy_, "dy", n);
    ensure_size(ctx_, carried_, "momentum", 2 * n);
    dx_.upload(ctx_.queue(), to_real<Real>(moves.dx));
    dy_.upload(ctx_.queue(), to_real<Real>(moves.dy));
    std::vector<Real> pxy(2 * n);
    for (std::size_t i = 0; i < n; ++i) {
      pxy[2 * i] = static_cast<Real>(carried.px[i]);
      pxy[2 * i + 1] = static_cast<Real>(carried.py[i]);
    }
    carried_.upload(ctx_.queue(), pxy);
    ArgSetter args(program_.apply_momentum_metric, "apply_momentum_metric");
    args(static_cast<cl_int>(n))(static_cast<Real>(beta))(static_cast<Real>(mix))(
        kind_)(fx_)(fy_)(r0_)(m11_)(m12_)(m22_)(dx_)(dy_)(carried_);
    launch(ctx_.queue(), program_.apply_momentum_metric, "apply_momentum_metric", n, program_.work_group);
    moves.dx = download(dx_, n);
    moves.dy = download(dy_, n);
    const std::vector<double> out = download(carried_, 2 * n);
    for (std::size_t i = 0; i < n; ++i) {
      carried.px[i] = out[2 * i];
      carried.py[i] = out[2 * i + 1];
    }
  }

  // Per-node |F|_M and kinetic terms on the device, summed here in node order as the reference sums.
  StepSums reduce_metric(const SimParticles& p, const ForceResult& forces, const MoveResult& moves) {
    const std::size_t n = p.size();
    upload_forces(p, forces);
    upload_metric(p);
    ensure_size(ctx_, dt2_, "dt2", n);
    dt2_.upload(ctx_.queue(), to_real<Real>(moves.dt2));
    ensure_size(ctx_, norm_, "metric_norm", n);
    ensure_size(ctx_, kinetic_, "kinetic", n);
    ArgSetter args(program_.metric_force_norms, "metric_force_norms");
    args(static_cast<cl_int>(n))(kind_)(fx_)(fy_)(dt2_)(m11_)(m12_)(m22_)(norm_)(kinetic_);
    launch(ctx_.queue(), program_.metric_force_norms, "metric_force_norms", n, program_.work_group);
    const std::vector<double> f = download(norm_, n), kinetic = download(kinetic_, n);
    StepSums s;
    for (std::size_t i = 0; i < n; ++i) {
      if (p.kind[i] == kSimFixed) continue;
      ++s.moving;
      s.sum_force += f[i];
      s.max_force = std::max(s.max_force, f[i]);
      s.sum_kinetic += kinetic[i];
    }
    return s;
  }

  void upload_metric(const SimParticles& p) {
    const std::size_t n = p.size();
    ensure_size(ctx_, m11_, "m11", n);
    ensure_size(ctx_, m12_, "m12", n);
    ensure_size(ctx_, m22_, "m22", n);
    m11_.upload(ctx_.queue(), to_real<Real>(p.m11));
    m12_.upload(ctx_.queue(), to_real<Real>(p.m12));
    m22_.upload(ctx_.queue(), to_real<Real>(p.m22));
  }

  std::vector<double> download(Buffer<Real>& b, std::size_t n) {
    std::vector<Real> v;
    b.download(ctx_.queue(), v, n);
    return std::vector<double>(v.begin(), v.end());
  }

  void upload_particles(const SimParticles& p) {
    const std::size_t n = p.size();
    ensure_size(ctx_, xy_, "xy", 2 * n);
    ensure_size(ctx_, q_, "q", n);
    ensure_size(ctx_, tx_, "tx", n);
    ensure_size(ctx_, ty_, "ty", n);
    ensure_size(ctx_, kind_, "kind", n);
    ensure_size(ctx_, prev_, "prev", n);
    ensure_size(ctx_, next_, "next", n);
    std::vector<Real> xy(2 * n);  // the packed layout of the kernels (x, y interleaved)
    for (std::size_t i = 0; i < n; ++i) {
      xy[2 * i] = static_cast<Real>(p.x[i]);
      xy[2 * i + 1] = static_cast<Real>(p.y[i]);
    }
    xy_.upload(ctx_.queue(), xy);
    q_.upload(ctx_.queue(), to_real<Real>(p.q));
    tx_.upload(ctx_.queue(), to_real<Real>(p.tx));
    ty_.upload(ctx_.queue(), to_real<Real>(p.ty));
    kind_.upload(ctx_.queue(), p.kind);
    prev_.upload(ctx_.queue(), p.prev);
    next_.upload(ctx_.queue(), p.next);
  }

  void upload_forces(const SimParticles& p, const ForceResult& forces) {
    const std::size_t n = p.size();
    ensure_size(ctx_, kind_, "kind", n);
    ensure_size(ctx_, fx_, "fx", n);
    ensure_size(ctx_, fy_, "fy", n);
    kind_.upload(ctx_.queue(), p.kind);
    fx_.upload(ctx_.queue(), to_real<Real>(forces.fx));
    fy_.upload(ctx_.queue(), to_real<Real>(forces.fy));
  }

  Context& ctx_;
  StepProgram program_;
  DeviceNeighbours<Real> neighbours_;
  reference::MetricNeighbourCache metric_rows_;
  Buffer<Real> xy_, q_, tx_, ty_, fx_, fy_, r0_, limit_, dx_, dy_, dt2_, partials_, carried_;
  Buffer<Real> m11_, m12_, m22_, norm_, kinetic_;  // metric mode only
  Buffer<std::uint8_t> kind_;
  Buffer<std::int32_t> prev_, next_, count_, index_, coincident_;
};

}  // namespace

std::unique_ptr<StepBackend> make_opencl_backend(Context& ctx, Precision precision, ForceLoop loop) {
  if (precision == Precision::Double) return std::make_unique<OpenclBackend<double>>(ctx, precision, loop);
  return std::make_unique<OpenclBackend<float>>(ctx, precision, loop);
}

}  // namespace pdmesh::ocl
