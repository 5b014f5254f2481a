// The pair-force floor in `pdmesh bench`'s tables; see bench_floor.hpp.
#include "app/bench/bench_floor.hpp"

#include <map>
#include <optional>
#include <tuple>

#include <fmt/format.h>

#include "core/errors.hpp"
#include "opencl/context.hpp"

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

const ocl::DeviceFloorResult* bench_device_floor(const ocl::DeviceInfo& device, ocl::Precision precision,
                                                 std::size_t nodes, int repeat, double cutoff, double lj_a) {
  using Key = std::tuple<int, int, bool, std::size_t, int, double, double>;
  static std::map<Key, std::optional<ocl::DeviceFloorResult>> measured;
  const Key key{device.platform, device.device, precision == ocl::Precision::Double, nodes, repeat, cutoff, lj_a};
  const auto it = measured.find(key);
  if (it != measured.end()) return it->second ? &*it->second : nullptr;
  FloorOptions options;
  options.nodes = nodes;
  options.repeats = repeat;
  options.cutoff = cutoff;
  options.lj_a = lj_a;
  std::optional<ocl::DeviceFloorResult> r;
  try {
    ocl::Context ctx(device);
    r = ocl::measure_device_floor(ctx, options, precision);
    fmt::print(stderr, "bench: {}\n", ocl::format_device_floor(*r));
  } catch (const DeviceError& e) {
    fmt::print(stderr, "bench: no device pair-force floor on {}: {}\n", device.name, e.what());
  } catch (const LimitError& e) {  // a buffer past the device's largest allocation
    fmt::print(stderr, "bench: no device pair-force floor on {}: {}\n", device.name, e.what());
  }
  const auto& kept = measured.emplace(key, std::move(r)).first->second;
  return kept ? &*kept : nullptr;
}

std::string device_floor_ms_cell(const ocl::DeviceFloorResult* floor) {
  if (floor == nullptr) return "-";
  return fmt::format("device {:.3f}", 1e3 * floor->device_seconds);
}

std::string device_floor_ratio_cell(const ocl::DeviceFloorResult* floor, double seconds_per_iteration) {
  if (floor == nullptr || !(floor->device_seconds > 0.0)) return "-";
  return fmt::format("{:.2f}", seconds_per_iteration / floor->device_seconds);
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
