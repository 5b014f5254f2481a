// Node files (docs/node-file.md): a plain-text dump of a NodeSet with its boundary connectivity,
// written with 17 significant digits so that reading it back gives bit-identical values.
#pragma once
#include <filesystem>
#include <string>
#include <vector>

#include "nodes/node_set.hpp"

namespace pdmesh {

struct NodeFile {
  NodeSet nodes;
  std::vector<std::string> curve_names;  // one per NodeSet::curve_nodes entry
};

// The file's text. curve_names must have one plain name (no white space) per curve_nodes entry;
// otherwise InputError.
std::string format_node_file(const NodeSet& nodes, const std::vector<std::string>& curve_names);

// Writes the node file atomically.
void write_node_file(const std::filesystem::path& path, const NodeSet& nodes,
                     const std::vector<std::string>& curve_names);

// Reads a node file. Throws InputError "FILE:LINE: ..." on anything malformed: a wrong header,
// bad counts, non-finite numbers, an unknown kind, curve indices or connectivity out of range.
NodeFile read_node_file(const std::filesystem::path& path);
NodeFile parse_node_file(const std::string& text, const std::string& source_name);

}  // namespace pdmesh
