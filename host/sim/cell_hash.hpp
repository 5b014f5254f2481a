// The hash of an integer cell coordinate pair (splitmix64 finaliser over both), shared by the
// reference neighbour search and the OpenCL backend's host-side binning.
#pragma once
#include <cstdint>

#include "core/mix64.hpp"

namespace pdmesh {

inline std::uint64_t cell_hash(std::int64_t cx, std::int64_t cy) {
  return mix64(static_cast<std::uint64_t>(cx) * 0x9E3779B97F4A7C15ULL ^ static_cast<std::uint64_t>(cy));
}

}  // namespace pdmesh
