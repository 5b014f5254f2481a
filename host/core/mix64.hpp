// splitmix64's finaliser: a cheap bijective 64-bit mix. Lattice keys (cell coordinates, packed
// quadtree keys) differ in few low bits, so hash tables index by mix64(key) rather than by the key.
// kernels/binning.cl (nb_hash) repeats it in OpenCL C for the device bins; test_device_neighbours
// checks that the device buckets are cell_hash's.
#pragma once
#include <cstdint>

namespace pdmesh {

constexpr std::uint64_t mix64(std::uint64_t k) {
  k ^= k >> 30;
  k *= 0xBF58476D1CE4E5B9ULL;
  k ^= k >> 27;
  k *= 0x94D049BB133111EBULL;
  k ^= k >> 31;
  return k;
}

}  // namespace pdmesh
