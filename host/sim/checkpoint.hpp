// Checkpoint files (docs/checkpoint.md): the node set and the simulation driver's state after some
// iterations, in exact hexadecimal floating point, so that a run continues bit-identically.
#pragma once
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "nodes/node_set.hpp"
#include "sim/simulation.hpp"

namespace pdmesh {

struct Checkpoint {
  // What identifies the case (key, value; values may contain spaces but no line breaks): a resumed
  // run refuses a checkpoint whose keys differ from its own case's.
  std::vector<std::pair<std::string, std::string>> case_keys;
  NodeSet nodes;
  SimState state;
};

// The file's text. Throws InputError on a case key with white space or a value with a line break.
std::string format_checkpoint(const Checkpoint& checkpoint);

// Writes the checkpoint atomically (core/atomic_file.hpp).
void write_checkpoint(const std::filesystem::path& path, const Checkpoint& checkpoint);

// Parses a checkpoint. Throws InputError "SOURCE:LINE: ..." on anything malformed: a wrong header,
// bad counts, non-finite or unparsable numbers, unknown kinds, node indices out of range, a
// missing end line (a truncated file).
Checkpoint parse_checkpoint(const std::string& text, const std::string& source_name);
Checkpoint read_checkpoint(const std::filesystem::path& path);

}  // namespace pdmesh
