// Persistent node ids (node_ids.hpp).
#include "nodes/node_ids.hpp"

#include <algorithm>

namespace pdmesh {

void number_new_nodes(NodeSet& nodes, std::int64_t& next) {
  if (nodes.id.size() != nodes.size()) nodes.id.assign(nodes.size(), -1);
  for (std::int64_t& id : nodes.id)
    if (id < 0) id = next++;
}

std::size_t ids_kept(const std::vector<std::int64_t>& before, const std::vector<std::int64_t>& now) {
  std::vector<std::int64_t> a = before, b = now;
  std::sort(a.begin(), a.end());
  std::sort(b.begin(), b.end());
  std::size_t n = 0;
  for (std::size_t i = 0, j = 0; i < a.size() && j < b.size();) {
    if (a[i] < b[j]) {
      ++i;
    } else if (b[j] < a[i]) {
      ++j;
    } else {
      ++n, ++i, ++j;
    }
  }
  return n;
}

}  // namespace pdmesh
