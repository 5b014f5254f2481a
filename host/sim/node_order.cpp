// Node numbering in spatial order; see node_order.hpp.
#include "sim/node_order.hpp"


#include <fmt/format.h>

#include "core/errors.hpp"
#include "geometry/hilbert.hpp"

namespace pdmesh {

const char* to_string(NodeOrder order) {
  switch (order) {
    case NodeOrder::Hilbert:
      return "hilbert";
    case NodeOrder::Auto:
      return "auto";
    case NodeOrder::Input:
      break;
  }
  return "input";
}

namespace {

template <typename T>
void permute(std::vector<T>& v, const std::vector<int>& old_of_new) {
  std::vector<T> out(old_of_new.size());
  for (std::size_t k = 0; k < old_of_new.size(); ++k) out[k] = v[static_cast<std::size_t>(old_of_new[k])];
  v = std::move(out);
}

}  // namespace

void permute_nodes(NodeSet& nodes, const std::vector<int>& old_of_new) {
  const std::size_t n = nodes.size();
  if (old_of_new.size() != n)
    throw SimulationError(fmt::format("a renumbering of {} entries for {} nodes", old_of_new.size(), n));
  std::vector<int> new_of_old(n, -1);
  for (std::size_t k = 0; k < n; ++k) {
    const int old = old_of_new[k];
    if (old < 0 || static_cast<std::size_t>(old) >= n || new_of_old[static_cast<std::size_t>(old)] >= 0)
      throw SimulationError(fmt::format("the renumbering of {} nodes is not a permutation (entry {}: {})", n, k, old));
    new_of_old[static_cast<std::size_t>(old)] = static_cast<int>(k);
  }
  const bool ids = nodes.has_ids();
  permute(nodes.x, old_of_new);
  permute(nodes.q, old_of_new);
  permute(nodes.kind, old_of_new);
  permute(nodes.curve, old_of_new);
  if (ids) permute(nodes.id, old_of_new);
  for (std::vector<int>& list : nodes.curve_nodes)
    for (int& node : list) node = new_of_old[static_cast<std::size_t>(node)];
}

std::vector<int> spatial_order(const NodeSet& nodes) { return hilbert_order(nodes.x); }

}  // namespace pdmesh
