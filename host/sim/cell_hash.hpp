// The hash of an integer cell coordinate pair (splitmix64 finaliser over both), shared by the
// reference neighbour search and the OpenCL backend's host-side binning.
#pragma once
#include <cstdint>

namespace pdmesh {

inline std::uint64_t cell_hash(std::int64_t cx, std::int64_t cy) {
  std::uint64_t h = static_cast<std::uint64_t>(cx) * 0x9E3779B97F4A7C15ULL ^ static_cast<std::uint64_t>(cy);
  h ^= h >> 30;
  h *= 0xBF58476D1CE4E5B9ULL;
  h ^= h >> 27;
  h *= 0x94D049BB133111EBULL;
  h ^= h >> 31;
  return h;
}

}  // namespace pdmesh
