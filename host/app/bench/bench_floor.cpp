// The pair-force floor in `pdmesh bench`'s tables; see bench_floor.hpp.
#include "app/bench/bench_floor.hpp"

#include <map>
#include <tuple>

#include <fmt/format.h>

namespace pdmesh {

const FloorResult& bench_floor(std::size_t nodes, int repeat, double cutoff, double lj_a) {
  static std::map<std::tuple<std::size_t, int, double, double>, FloorResult> measured;
  const auto key = std::make_tuple(nodes, repeat, cutoff, lj_a);
  const auto it = measured.find(key);
  if (it != measured.end()) return it->second;
  FloorOptions options;
  options.nodes = nodes;
  options.repeats = repeat;
  options.cutoff = cutoff;
  options.lj_a = lj_a;
  const FloorResult& r = measured.emplace(key, measure_pair_floor(options)).first->second;
  fmt::print(stderr, "bench: {}\n", format_floor(r));
  return r;
}

std::string floor_ms_cell(const FloorResult* floor) {
  if (floor == nullptr) return "-";
  return fmt::format("{:.3f} / {:.3f}", 1e3 * floor->scalar.wall, 1e3 * floor->vector.wall);
}

std::string floor_ratio_cell(const FloorResult* floor, double seconds_per_iteration) {
  if (floor == nullptr || !(floor->seconds() > 0.0)) return "-";
  return fmt::format("{:.2f}", seconds_per_iteration / floor->seconds());
}

std::string floor_cpu_ms_cell(const FloorResult* floor) {
  if (floor == nullptr) return "-";
  return fmt::format("{:.3f}", 1e3 * floor->best().cpu);
}

std::string floor_cpu_ratio_cell(const FloorResult* floor, double cpu_seconds_per_iteration) {
  if (floor == nullptr || !(floor->best().cpu > 0.0)) return "-";
  return fmt::format("{:.2f}", cpu_seconds_per_iteration / floor->best().cpu);
}

}  // namespace pdmesh
