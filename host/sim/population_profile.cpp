// The population event's part timers; see population_profile.hpp.
#include "sim/population_profile.hpp"

#include <cstdlib>
#include <cstring>
#include <string>
#include <utility>
#include <vector>

#include <fmt/format.h>

namespace pdmesh::population_profile {
namespace {

// An event runs on one thread at a time (the driver's); the parts keep their first-recorded order.
std::vector<std::pair<const char*, double>>& parts() {
  static std::vector<std::pair<const char*, double>> list;
  return list;
}

}  // namespace

void add(const char* part, double seconds) {
  for (auto& [name, total] : parts())
    if (std::strcmp(name, part) == 0) {
      total += seconds;
      return;
    }
  parts().emplace_back(part, seconds);
}

void print(const char* when) {
  static const bool on = std::getenv("PDMESH_POPULATION_PROFILE") != nullptr;
  if (on && !parts().empty()) {
    std::string line = fmt::format("population profile {}:", when);
    for (const auto& [name, total] : parts()) line += fmt::format(" {} {:.4f}", name, total);
    fmt::print(stderr, "{}\n", line);
  }
  parts().clear();
}

}  // namespace pdmesh::population_profile
