// The memory limit of a run (--max-memory): its default (a share of what the machine and the process
// may use), byte sizes as users write them ("4G"), and the refusal every stage that allocates in
// proportion to its input or to the node count raises before it allocates (docs/robustness.md,
// "Memory").
#pragma once
#include <cstdint>
#include <string>

namespace pdmesh {

// The default limit is this share of the least of the physical RAM, the address-space limit
// (ulimit -v) and the cgroup's memory.max: room for the page cache, the OpenCL runtime and the rest.
inline constexpr double kDefaultMemoryShare = 0.75;

struct MemoryLimit {
  std::uint64_t bytes = 0;  // 0: no limit
  std::string described;    // how messages name it: "--max-memory 4 GiB", or the default and its source
  bool limited() const { return bytes > 0; }
};

// The machine's physical RAM (sysconf), 0 when unknown.
std::uint64_t physical_memory_bytes();

// kDefaultMemoryShare of the least of the physical RAM, RLIMIT_AS and the cgroup (v2) memory.max, with
// its description ("the default --max-memory, 3/4 of the 23.4 GiB of RAM: 17.6 GiB"); no limit when
// none of those is known.
MemoryLimit default_memory_limit();

// "4G", "512M", "1.5GiB", "4096" (bytes): K, M, G, T are powers of 1024, with an optional "B" or "iB";
// `option` names the value in the InputError for anything else, and for 0 or less.
MemoryLimit parse_memory_limit(const std::string& text, const char* option = "--max-memory");

// "17.6 GiB", "512 MiB", "900 bytes".
std::string format_bytes(double bytes);

// Throws LimitError "<what> needs about N of memory, more than <limit.described>; <advice>" when
// `bytes` exceeds the limit (or is not finite).
void check_memory(const MemoryLimit& limit, double bytes, const std::string& what, const std::string& advice);

}  // namespace pdmesh
