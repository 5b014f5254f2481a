// Host binning + device gather of the neighbour rows; see device_neighbours.hpp.
#include "opencl/device_neighbours.hpp"

#include <array>
#include <chrono>
#include <cmath>

namespace pdmesh::ocl {
namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// Non-blocking: `host` must stay unchanged until the queue is synchronised (the counters download
// after the gather does that), so one rebuild waits on the device once, not once per array.
template <typename T>
std::size_t put(Context& ctx, Buffer<T>& b, const char* name, const std::vector<T>& host) {
  ensure_size(ctx, b, name, host.size());
  b.upload(ctx.queue(), host, false);
  return host.size() * sizeof(T);
}

constexpr std::array<std::uint32_t, 5> kZeroCounters{};

}  // namespace

template <typename Real>
std::size_t DeviceNeighbours<Real>::device_bytes() const {
  return count_.bytes() + scatter_count_.bytes() + scatter_index_.bytes() + index_.bytes() + level_.bytes() + table_id_.bytes() + table_cx_.bytes() +
         table_cy_.bytes() + cell_start_.bytes() + cell_nodes_.bytes();
}

template <typename Real>
NeighbourFlags DeviceNeighbours<Real>::build(const double* hx, const double* hy, const double* hq,
                                             const std::uint8_t* hkind, std::size_t n, double radius_factor,
                                             Buffer<Real>& x, Buffer<Real>& y, Buffer<Real>& q,
                                             Buffer<std::uint8_t>& kind, Buffer<std::int32_t>& prev,
                                             Buffer<std::int32_t>& next, int& stride, bool grow) {
  NeighbourFlags flags;
  if (stride < 2) stride = 2;
  for (std::size_t i = 0; i < n && flags.first_invalid < 0; ++i)
    if (!(std::isfinite(hx[i]) && std::isfinite(hy[i]) && std::isfinite(hq[i]) && hq[i] > 0.0))
      flags.first_invalid = static_cast<std::int32_t>(i);
  const auto t0 = std::chrono::steady_clock::now();
  if (flags.first_invalid < 0) build_neighbour_grids(hx, hy, hq, n, radius_factor, grids_);
  bin_seconds = seconds_since(t0);
  const auto t1 = std::chrono::steady_clock::now();
  uploaded_bytes = 0;
  if (flags.first_invalid < 0) {
    uploaded_bytes += put(ctx_, level_, "level", grids_.level);
    inv_cell_host_ = to_real<Real>(grids_.inv_cell);
    uploaded_bytes += put(ctx_, inv_cell_, "grid_inv_cell", inv_cell_host_);
    uploaded_bytes += put(ctx_, table_offset_, "grid_table_offset", grids_.table_offset);
    uploaded_bytes += put(ctx_, table_mask_, "grid_table_mask", grids_.table_mask);
    uploaded_bytes += put(ctx_, start_offset_, "grid_start_offset", grids_.start_offset);
    uploaded_bytes += put(ctx_, nodes_offset_, "grid_nodes_offset", grids_.nodes_offset);
    uploaded_bytes += put(ctx_, table_cx_, "table_cx", grids_.table_cx);
    uploaded_bytes += put(ctx_, table_cy_, "table_cy", grids_.table_cy);
    uploaded_bytes += put(ctx_, table_id_, "table_id", grids_.table_id);
    uploaded_bytes += put(ctx_, cell_start_, "cell_start", grids_.cell_start);
    uploaded_bytes += put(ctx_, cell_nodes_, "cell_nodes", grids_.cell_nodes);
  }
  ensure_size(ctx_, counters_, "neighbour_counters", 5);
  for (int attempt = 0; attempt < 3; ++attempt) {
    if (check_stride) check_stride(stride);
    const std::size_t entries = n * static_cast<std::size_t>(stride);
    ensure_size(ctx_, count_, "neighbour_count", n);
    ensure_size(ctx_, index_, "neighbour_index", entries);
    counters_.upload(ctx_.queue(), kZeroCounters.data(), kZeroCounters.size(), false);
    if (flags.first_invalid >= 0) {
      // Lists of an invalid node set are not built; the caller throws naming the node.
      flags.max_count = 0;
      break;
    }
    const Real radius = static_cast<Real>(radius_factor);
    // Pass 1: own cumulative grid, scattering to finer rows (scatter counts start at 0).
    ensure_size(ctx_, scatter_count_, "neighbour_scatter_count", n);
    ensure_size(ctx_, scatter_index_, "neighbour_scatter_index", entries);
    if (n > 0)  // a zero-sized fill is invalid OpenCL
      fill_zero(ctx_.queue(), scatter_count_.get(), n * sizeof(cl_int), "clearing 'neighbour_scatter_count'");
    ArgSetter a(program_.build_neighbours, "build_neighbours");
    a(static_cast<cl_int>(n))(static_cast<cl_int>(stride))(radius)(x)(y)(q)(kind)(prev)(next)(level_)(inv_cell_)(
        table_offset_)(table_mask_)(start_offset_)(nodes_offset_)(table_cx_)(table_cy_)(table_id_)(cell_start_)(
        cell_nodes_)(count_)(scatter_count_)(scatter_index_)(index_)(counters_);
    launch(ctx_.queue(), program_.build_neighbours, "build_neighbours", n, program_.work_group);
    // Pass 2: join, sort, pad; overflowing rows rescanned in reference order.
    ArgSetter b(program_.finish_neighbours, "finish_neighbours");
    b(static_cast<cl_int>(n))(static_cast<cl_int>(stride))(static_cast<cl_int>(grids_.levels))(radius)(x)(y)(q)(
        kind)(level_)(inv_cell_)(table_offset_)(table_mask_)(start_offset_)(nodes_offset_)(table_cx_)(table_cy_)(
        table_id_)(cell_start_)(cell_nodes_)(scatter_count_)(scatter_index_)(count_)(index_)(counters_);
    launch(ctx_.queue(), program_.finish_neighbours, "finish_neighbours", n, program_.work_group);
    std::vector<std::uint32_t> c;
    counters_.download(ctx_.queue(), c, 5);
    flags.max_count = static_cast<std::int32_t>(c[2]);
    flags.pairs_examined = c[3];
    flags.pairs_within = c[4];
    flags.overflow = flags.max_count > stride ? 1U : 0U;
    if (!flags.overflow || !grow) break;
    stride = (flags.max_count + 7) / 8 * 8;
  }
  // Boundary rows hold 2 entries even when no interior node exists (the reference's max_count).
  for (std::size_t i = 0; i < n; ++i)
    if (hkind[i] == kSimBoundary) {
      if (flags.max_count < 2) flags.max_count = 2;
      break;
    }
  gather_seconds = seconds_since(t1);
  return flags;
}

template class DeviceNeighbours<double>;
template class DeviceNeighbours<float>;

}  // namespace pdmesh::ocl
