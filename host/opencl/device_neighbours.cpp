// Host binning + device sizing, gather and sort of the compact neighbour rows; see device_neighbours.hpp.
#include "opencl/device_neighbours.hpp"

#include <array>
#include <chrono>
#include <cmath>

#include <fmt/format.h>

#include "core/errors.hpp"

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
  return count_.bytes() + offset_.bytes() + block_total_.bytes() + index_.bytes() + level_.bytes() + inv_cell_.bytes() +
         table_offset_.bytes() + table_mask_.bytes() + start_offset_.bytes() + nodes_offset_.bytes() + table_id_.bytes() +
         table_cx_.bytes() + table_cy_.bytes() + cell_start_.bytes() + cell_nodes_.bytes() + counters_.bytes();
}

template <typename Real>
NeighbourFlags DeviceNeighbours<Real>::build(const double* hx, const double* hy, const double* hq,
                                             const std::uint8_t* hkind, std::size_t n, double radius_factor,
                                             Buffer<Real>& x, Buffer<Real>& y, Buffer<Real>& q,
                                             Buffer<std::uint8_t>& kind, Buffer<std::int32_t>& prev,
                                             Buffer<std::int32_t>& next) {
  NeighbourFlags flags;
  attempts = 0;
  launches = 0;
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
  ensure_size(ctx_, offset_, "neighbour_offset", n + 1);
  // The counts of another node set say nothing about these rows: start from zero (a counting build).
  if (n != counted_n_ || count_.size() < n) {
    ensure_size(ctx_, count_, "neighbour_count", n);
    if (n > 0) fill_zero(ctx_.queue(), count_.get(), n * sizeof(cl_int), "clearing 'neighbour_count'");
    counted_total_ = 0;
  }
  if (flags.first_invalid >= 0 || n == 0) {
    // Lists of an invalid node set are not built (the caller throws naming the node); no rows at n = 0.
    fill_zero(ctx_.queue(), offset_.get(), sizeof(cl_ulong), "clearing 'neighbour_offset'");
    ensure_size(ctx_, index_, "neighbour_index", kRowTail);
    counted_n_ = 0;
    for (std::size_t i = 0; i < n; ++i)  // boundary rows hold 2 entries (the reference's max_count)
      if (hkind[i] == kSimBoundary) {
        flags.max_count = 2;
        break;
      }
    gather_seconds = seconds_since(t1);
    return flags;
  }
  const std::size_t wg = program_.work_group, groups = (n + wg - 1) / wg;
  ensure_size(ctx_, block_total_, "neighbour_block_total", groups + 1);
  const Real radius = static_cast<Real>(radius_factor);
  std::vector<std::uint32_t> c;
  int attempt = 0;
  for (;; ++attempt) {
    // Every capacity sum bounds offset[n]: sum(c + c >> s + m) <= total + total >> s + m n.
    const std::uint64_t bound = counted_total_ + (counted_total_ >> kSpareShift) +
                                static_cast<std::uint64_t>(kSpareMin) * n + kRowTail;
    if (index_.size() < bound) {
      if (check_entries) check_entries(bound);
      ensure_size(ctx_, index_, "neighbour_index", bound);
      // Slack slots are read (masked) by the vector force loop: give them defined contents.
      fill_zero(ctx_.queue(), index_.get(), index_.size() * sizeof(cl_int), "clearing 'neighbour_index'");
    }
    const cl_ulong entries_size = index_.size() - kRowTail;
    ArgSetter s(program_.row_capacity_scan, "row_capacity_scan");
    s(static_cast<cl_int>(n))(static_cast<cl_int>(kSpareShift))(static_cast<cl_int>(kSpareMin))(count_)(offset_)(
        block_total_);
    launch(ctx_.queue(), program_.row_capacity_scan, "row_capacity_scan", n, wg);
    ArgSetter b(program_.row_block_offsets, "row_block_offsets");
    b(static_cast<cl_int>(groups))(block_total_);
    launch(ctx_.queue(), program_.row_block_offsets, "row_block_offsets", wg, wg);
    ArgSetter o(program_.row_offsets_add, "row_offsets_add");
    o(static_cast<cl_int>(n))(offset_)(block_total_);
    launch(ctx_.queue(), program_.row_offsets_add, "row_offsets_add", n, wg);
    fill_zero(ctx_.queue(), count_.get(), n * sizeof(cl_int), "clearing 'neighbour_count'");
    counters_.upload(ctx_.queue(), kZeroCounters.data(), kZeroCounters.size(), false);
    ArgSetter g(program_.gather_rows, "gather_rows");
    g(static_cast<cl_int>(n))(radius)(x)(y)(q)(kind)(prev)(next)(level_)(inv_cell_)(table_offset_)(table_mask_)(
        start_offset_)(nodes_offset_)(table_cx_)(table_cy_)(table_id_)(cell_start_)(cell_nodes_)(offset_)(count_)(
        entries_size)(index_)(counters_);
    launch(ctx_.queue(), program_.gather_rows, "gather_rows", n, wg);
    ArgSetter r(program_.sort_rows, "sort_rows");
    r(static_cast<cl_int>(n))(kind)(offset_)(count_)(entries_size)(index_)(counters_);
    launch(ctx_.queue(), program_.sort_rows, "sort_rows", n, wg);
    launches += 5;
    counters_.download(ctx_.queue(), c, 5);
    counted_n_ = n;
    counted_total_ = c[1];
    if (c[0] == 0) break;
    // The counts are exact now (rows count past their capacity): the next gather fits.
    if (attempt >= 2)
      throw SimulationError(fmt::format("neighbour rows still outgrow their capacities after {} gathers", attempt + 1));
  }
  attempts = attempt + 1;
  flags.max_count = static_cast<std::int32_t>(c[2]);
  flags.pairs_examined = c[3];
  flags.pairs_within = c[4];
  gather_seconds = seconds_since(t1);
  return flags;
}

template class DeviceNeighbours<double>;
template class DeviceNeighbours<float>;

}  // namespace pdmesh::ocl
