// FlatKeyMap (core/flat_key_map.hpp), the spacing pipeline's lattice table: the same answers as
// std::unordered_map over inserts, repeated inserts, lookups of absent keys and growth; and mix64,
// the hash it and the cell lists index by.
#include <catch2/catch.hpp>

#include <cstdint>
#include <random>
#include <stdexcept>
#include <unordered_map>

#include "core/flat_key_map.hpp"
#include "core/mix64.hpp"
#include "sim/cell_hash.hpp"

using namespace pdmesh;

TEST_CASE("FlatKeyMap agrees with std::unordered_map through growth", "[core]") {
  std::mt19937_64 rng(7);
  FlatKeyMap<double> map;
  std::unordered_map<std::uint64_t, double> oracle;
  // Lattice-like keys (x << 32 | y on a small grid, many repeats) and arbitrary 64-bit keys.
  for (int i = 0; i < 200000; ++i) {
    const std::uint64_t key = i % 3 == 0 ? rng() >> 1 : ((rng() % 300) << 32) | (rng() % 300);
    const double value = static_cast<double>(i);
    const auto [stored, inserted] = map.try_emplace(key, value);
    const auto [it, oracle_inserted] = oracle.try_emplace(key, value);
    REQUIRE(inserted == oracle_inserted);
    REQUIRE(*stored == it->second);
    if (i % 7 == 0) *stored = it->second = -value;  // values are writable through the result
  }
  REQUIRE(map.size() == oracle.size());
  for (const auto& [key, value] : oracle) {
    REQUIRE(map.find(key) != nullptr);
    REQUIRE(map.at(key) == value);
  }
  // Absent keys: none of the grid keys beyond x = 300 was inserted.
  for (std::uint64_t x = 300; x < 310; ++x) {
    CHECK(map.find((x << 32) | 5) == nullptr);
    CHECK_THROWS_AS(map.at((x << 32) | 5), std::out_of_range);
  }
}

TEST_CASE("FlatKeyMap refuses its reserved key and keeps entries across reserve", "[core]") {
  FlatKeyMap<int> map;
  CHECK_THROWS_AS(map.try_emplace(FlatKeyMap<int>::kEmpty, 1), std::invalid_argument);
  CHECK(map.size() == 0);
  for (int i = 0; i < 100; ++i) map.try_emplace(static_cast<std::uint64_t>(i) * 977, i);
  map.reserve(100000);
  CHECK(map.size() == 100);
  for (int i = 0; i < 100; ++i) CHECK(map.at(static_cast<std::uint64_t>(i) * 977) == i);
  CHECK_FALSE(map.try_emplace(977, 5).second);
  CHECK(map.at(977) == 1);
}

TEST_CASE("mix64 is splitmix64's finaliser", "[core]") {
  // splitmix64 seeded with 0 returns mix64 of its first state, the golden-ratio increment; its first
  // two outputs are published (Vigna's reference implementation).
  const std::uint64_t gamma = 0x9E3779B97F4A7C15ULL;
  CHECK(mix64(gamma) == 0xE220A8397B1DCDAFULL);
  CHECK(mix64(2 * gamma) == 0x6E789E6AA1B965F4ULL);
  // cell_hash (sim/cell_hash.hpp, also computed by kernels/binning.cl) is mix64 of the packed pair.
  CHECK(cell_hash(3, -5) == mix64(3 * gamma ^ static_cast<std::uint64_t>(std::int64_t{-5})));
}
