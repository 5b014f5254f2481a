// The memory limit: its default from the machine, parsing, formatting and the refusal; see
// memory_budget.hpp.
#include "core/memory_budget.hpp"

#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <fmt/format.h>

#include "core/errors.hpp"

namespace pdmesh {

namespace {

constexpr double kKiB = 1024.0;

// cgroup v2's memory.max of this process's group ("max" or absent: none).
std::uint64_t cgroup_memory_max() {
  std::ifstream in("/sys/fs/cgroup/memory.max");
  std::string text;
  if (!(in >> text) || text == "max") return 0;
  char* end = nullptr;
  const unsigned long long v = std::strtoull(text.c_str(), &end, 10);
  return end && *end == '\0' ? static_cast<std::uint64_t>(v) : 0;
}

}  // namespace

std::uint64_t physical_memory_bytes() {
  const long pages = sysconf(_SC_PHYS_PAGES);
  const long page = sysconf(_SC_PAGE_SIZE);
  if (pages <= 0 || page <= 0) return 0;
  return static_cast<std::uint64_t>(pages) * static_cast<std::uint64_t>(page);
}

std::string format_bytes(double bytes) {
  if (!std::isfinite(bytes)) return fmt::format("{} bytes", bytes);
  const char* units[] = {"KiB", "MiB", "GiB", "TiB", "PiB", "EiB"};
  if (bytes < kKiB) return fmt::format("{:.0f} bytes", bytes);
  double v = bytes / kKiB;
  int u = 0;
  while (v >= kKiB && u < 5) {
    v /= kKiB;
    ++u;
  }
  return fmt::format("{:.{}f} {}", v, v < 10.0 ? 2 : v < 100.0 ? 1 : 0, units[u]);
}

MemoryLimit default_memory_limit() {
  std::uint64_t least = 0;
  std::string of;
  const auto consider = [&](std::uint64_t bytes, const std::string& what) {
    if (bytes == 0 || (least != 0 && bytes >= least)) return;
    least = bytes;
    of = fmt::format("{} {}", format_bytes(static_cast<double>(bytes)), what);
  };
  consider(physical_memory_bytes(), "of RAM");
  rlimit as{};
  if (getrlimit(RLIMIT_AS, &as) == 0 && as.rlim_cur != RLIM_INFINITY)
    consider(static_cast<std::uint64_t>(as.rlim_cur), "address-space limit (ulimit -v)");
  consider(cgroup_memory_max(), "cgroup memory.max");
  MemoryLimit limit;
  if (least == 0) return limit;
  limit.bytes = static_cast<std::uint64_t>(kDefaultMemoryShare * static_cast<double>(least));
  limit.described =
      fmt::format("the default --max-memory {} (3/4 of the {})", format_bytes(static_cast<double>(limit.bytes)), of);
  return limit;
}

MemoryLimit parse_memory_limit(const std::string& text, const char* option) {
  const auto bad = [&] {
    return InputError(
        fmt::format("{} {}: expected a size in bytes, optionally with a suffix K, M, G or T "
                    "(powers of 1024), e.g. 4G or 512M, greater than 0",
                    option, text.size() > 100 ? text.substr(0, 100) + "..." : text));
  };
  std::size_t used = 0;
  double value = 0.0;
  try {
    value = std::stod(text, &used);
  } catch (const std::exception&) {
    throw bad();
  }
  std::string suffix = text.substr(used);
  std::transform(suffix.begin(), suffix.end(), suffix.begin(), [](unsigned char c) { return std::toupper(c); });
  if (suffix.size() > 1 && (suffix.ends_with("IB") || suffix.ends_with("B")))
    suffix.erase(suffix.size() - (suffix.ends_with("IB") ? 2 : 1));
  double unit = 1.0;
  if (suffix == "K")
    unit = kKiB;
  else if (suffix == "M")
    unit = kKiB * kKiB;
  else if (suffix == "G")
    unit = kKiB * kKiB * kKiB;
  else if (suffix == "T")
    unit = kKiB * kKiB * kKiB * kKiB;
  else if (!suffix.empty() && suffix != "B")
    throw bad();
  const double bytes = value * unit;
  // At least one byte, and within what a 64-bit size holds.
  if (!(bytes >= 1.0) || !(bytes < 1.8e19)) throw bad();
  MemoryLimit limit;
  limit.bytes = static_cast<std::uint64_t>(bytes);
  limit.described = fmt::format("{} {}", option, format_bytes(bytes));
  return limit;
}

void check_memory(const MemoryLimit& limit, double bytes, const std::string& what, const std::string& advice) {
  if (!limit.limited() || (std::isfinite(bytes) && bytes <= static_cast<double>(limit.bytes))) return;
  throw LimitError(
      fmt::format("{} needs about {} of memory, more than {}; {}", what, format_bytes(bytes), limit.described, advice));
}

}  // namespace pdmesh
