// The device memory a device-resident run needs, and its refusal when the device has less
// (device_simulation.hpp, docs/robustness.md section 4).
#include <fmt/format.h>

#include "core/errors.hpp"
#include "opencl/device_simulation.hpp"

namespace pdmesh::ocl {
namespace {

// The neighbour list's initial row stride (DeviceRun::stride_ starts there).
constexpr std::size_t kInitialStride = 16;

}  // namespace

DeviceMemoryNeed device_memory_need(std::size_t nodes, std::size_t boundary_nodes, std::uint64_t field_bytes,
                                    std::size_t real_bytes) {
  DeviceMemoryNeed need;
  const std::uint64_t n = nodes, r = real_bytes;
  // Per node: x, y, q twice, tx, ty, the build copies of x, y, q, the clearance budget and a 4-value
  // candidate record (16 reals); kind (1 byte); prev, next, bslot, candidate index, leaf, neighbour
  // count (6 ints); the neighbour index (kInitialStride ints). Per boundary node a 4-value record.
  // Lower bounds: the neighbour binning adds its grids, the host records their buffers, and the
  // rows grow when a node has more neighbours.
  need.largest = 4 * n * kInitialStride;
  need.total = n * (16 * r + 1 + 6 * 4) + need.largest + 4 * r * boundary_nodes + field_bytes;
  return need;
}

void check_device_memory(const DeviceInfo& device, std::size_t nodes, std::size_t boundary_nodes,
                         std::uint64_t field_bytes, std::size_t real_bytes) {
  const DeviceMemoryNeed need = device_memory_need(nodes, boundary_nodes, field_bytes, real_bytes);
  if (need.total <= device.global_memory && need.largest <= device.max_allocation) return;
  const DeviceMemoryNeed in_float = device_memory_need(nodes, boundary_nodes, field_bytes, 4);
  throw LimitError(fmt::format(
      "{} nodes need at least {} bytes of device memory in {} (the largest buffer, the neighbour list, {} bytes), "
      "but {} has {} bytes of global memory (CL_DEVICE_GLOBAL_MEM_SIZE) and allows {} bytes per buffer "
      "(CL_DEVICE_MAX_MEM_ALLOC_SIZE): {}use --device host (the host reference, in host memory) or a coarser "
      "spacing (fewer nodes)",
      nodes, need.total, real_bytes == 4 ? "float" : "double", need.largest, device.name, device.global_memory,
      device.max_allocation,
      real_bytes == 4 ? "" : fmt::format("use --precision float (at least {} bytes), ", in_float.total)));
}

}  // namespace pdmesh::ocl
