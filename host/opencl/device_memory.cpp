// The device memory a device-resident run needs, and its refusal when the device has less
// (device_simulation.hpp, docs/robustness.md section 4): before the first allocation at the initial
// row estimate, and again whenever the neighbour rows grow.
#include <limits>

#include <fmt/format.h>

#include "core/errors.hpp"
#include "opencl/device_simulation.hpp"

namespace pdmesh::ocl {

DeviceMemoryNeed device_memory_need(std::size_t nodes, std::size_t boundary_nodes, std::uint64_t field_bytes,
                                    std::size_t real_bytes, int entries_per_node, bool momentum) {
  DeviceMemoryNeed need;
  const std::uint64_t n = nodes, r = real_bytes;
  // Per node: x, y, q twice, tx, ty, the build copies of x, y, q, the clearance budget and a 4-value
  // candidate record (16 reals); kind (1 byte); prev, next, bslot, candidate index, leaf, neighbour
  // count, level (7 ints); the row offset (8 bytes); the compact neighbour rows (entries_per_node ints
  // per node on average). Per boundary node a 4-value record, its arc position twice (boundary_snap's
  // Jacobi rule) and its slot (node, curve, entry: 3 ints). Lower bounds: the neighbour binning adds
  // its grids, the curves' polylines and the host records their buffers. With momentum 2 reals more
  // per node: the carried move.
  need.largest = 4 * n * static_cast<std::uint64_t>(entries_per_node);
  need.total =
      n * ((momentum ? 18 : 16) * r + 1 + 7 * 4 + 8) + need.largest + (6 * r + 12) * boundary_nodes + field_bytes;
  return need;
}

void check_device_memory(const DeviceInfo& device, std::size_t nodes, std::size_t boundary_nodes,
                         std::uint64_t field_bytes, std::size_t real_bytes, int entries_per_node, bool momentum) {
  // Node indices, and 5 values per node in the record buffers, are 32-bit on the device.
  constexpr std::size_t kMaxNodes = static_cast<std::size_t>(std::numeric_limits<std::int32_t>::max()) / 8;
  if (nodes > kMaxNodes)
    throw LimitError(
        fmt::format("{} nodes are more than the device-resident run indexes ({} at most): use --device "
                    "host or a coarser spacing",
                    nodes, kMaxNodes));
  const DeviceMemoryNeed need =
      device_memory_need(nodes, boundary_nodes, field_bytes, real_bytes, entries_per_node, momentum);
  if (need.total <= device.global_memory && need.largest <= device.max_allocation) return;
  const DeviceMemoryNeed in_float =
      device_memory_need(nodes, boundary_nodes, field_bytes, 4, entries_per_node, momentum);
  const bool grown = entries_per_node > kInitialStride;
  throw LimitError(fmt::format(
      "{} nodes need at least {} bytes of device memory in {} (the largest buffer, the neighbour rows at {} "
      "entries per node, {} bytes{}), but {} has {} bytes of global memory (CL_DEVICE_GLOBAL_MEM_SIZE) and allows {} "
      "bytes per buffer (CL_DEVICE_MAX_MEM_ALLOC_SIZE): {}use --device host (the host reference, in host memory) or "
      "a {}spacing (fewer nodes)",
      nodes, need.total, real_bytes == 4 ? "float" : "double", entries_per_node, need.largest,
      grown ? ": nodes have that many neighbours within the list radius on average" : "", device.name,
      device.global_memory, device.max_allocation,
      real_bytes == 4 || in_float.total > device.global_memory || in_float.largest > device.max_allocation
          ? ""
          : fmt::format("use --precision float (at least {} bytes), ", in_float.total),
      grown ? "less graded " : "coarser "));
}

}  // namespace pdmesh::ocl
