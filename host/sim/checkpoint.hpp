// Checkpoint files (docs/checkpoint.md): the node set and the simulation driver's state after some
// iterations, in exact hexadecimal floating point, so that a run continues bit-identically.
#pragma once
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "geometry/geometry_tree.hpp"
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

// Throws InputError "SOURCE: the checkpoint does not fit the case's geometry: ..." unless the state
// can be continued on this geometry: one node list per curve, each from a Fixed node to a Fixed node
// with only Fixed and Boundary nodes between, every Boundary node listed once on its own curve,
// arc positions strictly increasing from 0 to the curve's length, positive spacings and time steps,
// every node within the geometry's extents, tangents no longer than 1, history rows numbered 1, 2, ...
// (host/sim/checkpoint_check.cpp). An interior node outside the domain is not refused: a float
// device run can round one just across the boundary, and the next move snaps it onto a curve.
void check_checkpoint_fits(const Checkpoint& checkpoint, const GeometryTree& tree, const std::string& source);

}  // namespace pdmesh
