// Neighbour lists on the device: the host bins (O(N) flat grids, neighbour_grids.hpp), the device
// gathers each row in two passes (kernels/neighbours.cl: own-level scan with scatter into a separate
// buffer, then join + sort). Used by the StepBackend and the device-resident run.
#pragma once
#include <cstdint>
#include <functional>

#include "opencl/buffer.hpp"
#include "opencl/neighbour_grids.hpp"
#include "opencl/step_program.hpp"
#include "sim/step_backend.hpp"

namespace pdmesh::ocl {

template <typename Real>
class DeviceNeighbours {
 public:
  DeviceNeighbours(Context& ctx, StepProgram& program) : ctx_(ctx), program_(program) {}

  // Builds rows of `stride` for n nodes (device arrays x, y, q, kind, prev, next) from host copies
  // hx, hy, hq of the same positions (to bin), interior radius radius_factor * q_i. Sets count and
  // index and the flags (first_invalid from a host scan). With grow, a row overflow grows stride to
  // the next multiple of 8 of the largest count and builds again (the host retry). Before the row
  // buffers are allocated at a stride, check_stride (when set) is called with it: it throws when the
  // device cannot hold n rows of that stride (the device-resident run's check_device_memory).
  NeighbourFlags build(const double* hx, const double* hy, const double* hq, const std::uint8_t* hkind, std::size_t n,
                       double radius_factor, Buffer<Real>& x, Buffer<Real>& y, Buffer<Real>& q,
                       Buffer<std::uint8_t>& kind, Buffer<std::int32_t>& prev, Buffer<std::int32_t>& next,
                       int& stride, bool grow);

  Buffer<std::int32_t>& count() { return count_; }
  Buffer<std::int32_t>& index() { return index_; }
  std::size_t device_bytes() const;
  std::function<void(int stride)> check_stride;
  std::size_t uploaded_bytes = 0;  // by the last build
  double bin_seconds = 0.0;        // host binning, last build
  double gather_seconds = 0.0;     // device gather (incl. uploads), last build

 private:
  Context& ctx_;
  StepProgram& program_;
  NeighbourGrids grids_;
  Buffer<std::int32_t> count_, scatter_count_, scatter_index_, index_, level_, table_offset_, table_mask_, start_offset_, nodes_offset_, table_id_,
      cell_start_, cell_nodes_;
  Buffer<std::uint32_t> counters_;
  Buffer<Real> inv_cell_;
  std::vector<Real> inv_cell_host_;  // kept alive for the non-blocking upload
  Buffer<std::int64_t> table_cx_, table_cy_;
};

}  // namespace pdmesh::ocl
