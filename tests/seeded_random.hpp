// A seeded, platform-independent random number source for the tests: the same doubles on every
// standard library (std::uniform_real_distribution's are not).
#pragma once
#include <random>

namespace pdmesh_test {

// 53 random bits mapped to [0, 1).
inline double unit(std::mt19937_64& rng) { return static_cast<double>(rng() >> 11) * 0x1.0p-53; }

}  // namespace pdmesh_test
