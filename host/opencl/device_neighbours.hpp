// Neighbour lists on the device in compact rows (CSR): the host bins (O(N) flat grids,
// neighbour_grids.hpp), the device sizes the rows (a prefix sum over capacities), gathers them
// (integer atomics per row) and sorts them (kernels/neighbours.cl). Used by the StepBackend and the
// device-resident run.
#pragma once
#include <cstdint>
#include <functional>

#include "opencl/buffer.hpp"
#include "opencl/neighbour_grids.hpp"
#include "opencl/step_program.hpp"
#include "sim/step_backend.hpp"

namespace pdmesh::ocl {

// Row i of a build holds count()[i] entries at index()[offset()[i] ..] (64-bit offsets, n + 1 of them;
// offset[i + 1] - offset[i] is the row's capacity, >= its count). Interior rows are sorted ascending,
// boundary rows are [prev, next]: the reference's rows (host/sim/reference/binning.cpp), slot by slot,
// never truncated. index() has kRowTail readable entries past offset[n] (the vector force loop reads
// whole chunks of 8).
inline constexpr std::size_t kRowTail = 8;

template <typename Real>
class DeviceNeighbours {
 public:
  DeviceNeighbours(Context& ctx, StepProgram& program) : ctx_(ctx), program_(program) {}

  // Builds the rows of n nodes (device arrays x, y, q, kind, prev, next) from host copies hx, hy, hq of
  // the same positions (to bin), interior radius radius_factor * q_i. Row capacities are the counts
  // of the last build plus slack (kSpareShift, kSpareMin); when a row outgrows its capacity the build
  // runs again with the counts it found (exact), so a first build, or one after the node set changed,
  // costs two gathers. Sets the flags (first_invalid from a host scan; overflow stays 0: rows are
  // never truncated). Before the index buffer grows, check_entries (when set) is called with its new
  // size: it throws when the device cannot hold it (the device-resident run's check_device_memory).
  NeighbourFlags build(const double* hx, const double* hy, const double* hq, const std::uint8_t* hkind, std::size_t n,
                       double radius_factor, Buffer<Real>& x, Buffer<Real>& y, Buffer<Real>& q,
                       Buffer<std::uint8_t>& kind, Buffer<std::int32_t>& prev, Buffer<std::int32_t>& next);

  // A row's capacity is c + (c >> kSpareShift) + kSpareMin for the count c of the last build: rows
  // grow a little between rebuilds as nodes move (docs/performance.md, issue 15 neighbours).
  static constexpr int kSpareShift = 3, kSpareMin = 2;

  Buffer<std::int32_t>& count() { return count_; }
  Buffer<std::uint64_t>& offset() { return offset_; }
  Buffer<std::int32_t>& index() { return index_; }
  std::size_t device_bytes() const;
  std::function<void(std::uint64_t entries)> check_entries;
  std::size_t uploaded_bytes = 0;  // by the last build
  double bin_seconds = 0.0;        // host binning, last build
  double gather_seconds = 0.0;     // device gather (incl. uploads), last build
  int attempts = 0;                // gathers of the last build (2 when a row outgrew its capacity)
  int launches = 0;                // kernel launches of the last build

 private:
  Context& ctx_;
  StepProgram& program_;
  NeighbourGrids grids_;
  Buffer<std::int32_t> count_, index_, level_, table_offset_, table_mask_, start_offset_, nodes_offset_, table_id_,
      cell_start_, cell_nodes_;
  Buffer<std::uint64_t> offset_, block_total_;
  Buffer<std::uint32_t> counters_;
  Buffer<Real> inv_cell_;
  std::vector<Real> inv_cell_host_;  // kept alive for the non-blocking upload
  Buffer<std::int64_t> table_cx_, table_cy_;
  std::size_t counted_n_ = 0;       // nodes whose counts count_ holds (the last build's n; 0: none)
  std::uint64_t counted_total_ = 0;  // their sum
};

}  // namespace pdmesh::ocl
