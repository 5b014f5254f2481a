// The mesh nodes (the thesis' particles): positions, desired spacing q, kind, and the ordered
// boundary connectivity per curve that boundary handling and the triangulation rely on.
#pragma once
#include <cstdint>
#include <vector>

#include "core/vec2.hpp"

namespace pdmesh {

enum class NodeKind : std::uint8_t {
  Fixed = 0,     // a critical point: never moves
  Boundary = 1,  // slides along its curve
  Interior = 2,  // moves freely inside the domain
};

const char* to_string(NodeKind kind);

struct NodeSet {
  std::vector<Vec2> x;    // positions
  std::vector<double> q;  // desired spacing at x
  std::vector<NodeKind> kind;
  std::vector<int> curve;  // curve of a Boundary node; first curve of a Fixed node; -1 for Interior
  // For each geometry curve, its nodes in order from the curve's first point to its last,
  // both end points included (those are Fixed nodes shared with the neighbouring curves).
  std::vector<std::vector<int>> curve_nodes;
  // Per curve_nodes entry: 1 for an embedded constraint (Curve::constraint), whose chain of edges
  // has the domain on both sides; empty when no curve is one.
  std::vector<std::uint8_t> constraint_curves;
  // Persistent node ids (a moving-geometry run, docs/motion.md): empty, or one per node. While the
  // column is there, every edit keeps it parallel: add() appends -1 (a new node, numbered by the
  // caller, nodes/node_ids.hpp), removals drop the removed nodes' ids, the cleanup carries them.
  std::vector<std::int64_t> id;

  std::size_t size() const { return x.size(); }
  bool has_ids() const { return !id.empty() && id.size() == x.size(); }
  int add(Vec2 p, double spacing, NodeKind k, int c) {
    if (has_ids()) id.push_back(-1);
    x.push_back(p);
    q.push_back(spacing);
    kind.push_back(k);
    curve.push_back(c);
    return static_cast<int>(x.size()) - 1;
  }
  std::size_t count(NodeKind k) const {
    std::size_t n = 0;
    for (auto v : kind) n += (v == k);
    return n;
  }
};

}  // namespace pdmesh
