// The cleaned mesh and its node set (cleaned_nodes.hpp).
#include "cleanup/cleaned_nodes.hpp"

#include <utility>
#include <vector>

namespace pdmesh::cleanup {

void cleaned_mesh_and_nodes(const EditableMesh& m, const Mesh& mesh, const NodeSet& nodes, const SpacingField& spacing,
                            Mesh& out_mesh, NodeSet& out) {
  std::vector<int> old_of_new;
  std::vector<std::vector<int>> curve_nodes;
  out_mesh = m.to_mesh(mesh, curve_nodes, old_of_new);
  out.x = out_mesh.points;
  out.kind = out_mesh.kind;
  out.curve_nodes = std::move(curve_nodes);
  out.constraint_curves = nodes.constraint_curves;
  // Persistent ids: a node the cleanup kept keeps its id; one it inserted is new (-1).
  const bool ids = nodes.has_ids();
  for (std::size_t k = 0; k < old_of_new.size(); ++k) {
    const auto a = static_cast<std::size_t>(old_of_new[k]);
    const bool original = a < nodes.size();
    out.q.push_back(original ? nodes.q[a] : spacing.at(out.x[k]));
    out.curve.push_back(original ? nodes.curve[a] : m.curve[a]);
    if (ids) out.id.push_back(original ? nodes.id[a] : -1);
  }
}

}  // namespace pdmesh::cleanup
