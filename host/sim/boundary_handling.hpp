// Boundary handling after each move (thesis ch. 5, "New Node Locations", fig. 5.7), host only:
// boundary nodes are re-snapped to their own curve without passing a neighbour or a critical
// point; interior nodes that leave the domain are snapped to the closest curve and join it.
#pragma once
#include <cstddef>
#include <functional>
#include <vector>

#include "geometry/curve_projection.hpp"
#include "geometry/geometry_tree.hpp"
#include "nodes/node_set.hpp"

namespace pdmesh {

struct BoundaryCounts {
  std::size_t snapped = 0;  // interior nodes that left the domain and became boundary nodes
  std::size_t clamped = 0;  // boundary nodes whose move was cut short at the allowed arc range
};

class BoundaryHandler {
 public:
  // A boundary node may move at most this fraction of the arc gap to each curve neighbour, so
  // neighbours can neither cross nor meet even when both move towards each other.
  static constexpr double kMaxGapFraction = 0.45;
  // A snapped interior node is placed in the middle part of the gap it lands in: at least this
  // fraction of the gap away from both nodes, so it never coincides with one (or a critical point).
  static constexpr double kInsertMargin = 0.25;

  // Computes the arc position of every curve_nodes entry. Throws SimulationError when a list does
  // not start/end with the curve's end points or a Boundary node is off its curve's order.
  BoundaryHandler(const GeometryTree& tree, const NodeSet& nodes);

  // Moves every node by (dx, dy) (Fixed nodes ignore it) and handles the boundary: updates
  // nodes.x, kind, curve and curve_nodes. Nodes are processed in index order (reproducible).
  BoundaryCounts apply(NodeSet& nodes, const std::vector<double>& dx, const std::vector<double>& dy);
  // apply() with the interior step restricted to `interior` (ascending node indices): for the
  // device-resident run, whose device already moved every other interior node (surely inside).
  // dx, dy are read only at Boundary nodes and at `interior`.
  BoundaryCounts apply_subset(NodeSet& nodes, const std::vector<double>& dx, const std::vector<double>& dy,
                              const std::vector<int>& interior);
  // apply_subset without the boundary nodes, which the device re-snapped already (kernels/boundary.cl):
  // the interior step of `interior` only, node interior[k] moved by moves[k] (the device's few
  // candidates: no array of every node). before_snap (when set) runs before each escaped node is
  // snapped onto a curve, which reads the arc positions: the device run brings them up to date there.
  BoundaryCounts apply_interior(NodeSet& nodes, const std::vector<int>& interior, const std::vector<Vec2>& moves,
                                const std::function<void()>& before_snap);

  const GeometryTree& tree() const { return tree_; }
  // Unit tangent of a Boundary node (zero for other kinds).
  Vec2 tangent(int node) const { return tangent_[static_cast<std::size_t>(node)]; }
  // Arc positions parallel to NodeSet::curve_nodes.
  const std::vector<std::vector<double>>& arcs() const { return arcs_; }
  // Per-node tangents (zero except at Boundary nodes).
  const std::vector<Vec2>& tangents() const { return tangent_; }
  // Replaces the arc positions and tangents with saved ones (a checkpoint): they are updated
  // incrementally, so recomputing them from the node positions would not continue bit-identically.
  // Throws InputError when the sizes do not match nodes.
  void restore(const NodeSet& nodes, std::vector<std::vector<double>> arcs, std::vector<Vec2> tangents);
  // Previous and next node along the curve of each Boundary node (-1 for other kinds).
  void curve_neighbours(const NodeSet& nodes, std::vector<int>& prev, std::vector<int>& next) const;

  // Edits for population control (sim/population.cpp); each keeps curve_nodes, the arc positions, the
  // tangents and the clearance budgets parallel to the node set.
  // Appends an Interior node at p with spacing q (no budget yet: its first move gets the exact test).
  int add_interior(NodeSet& nodes, Vec2 p, double q);
  // Inserts a Boundary node on curve `curve` at arc position `arc`, which must lie strictly between
  // the arc positions of curve_nodes[curve][pos - 1] and [pos]; it becomes entry pos. Returns its index.
  int add_boundary(NodeSet& nodes, int curve, std::size_t pos, double arc, double q);
  // Moves Interior node `node` to p (a merge); its budget is spent.
  void move_interior(NodeSet& nodes, int node, Vec2 p);
  // Removes the flagged nodes (never Fixed ones: SimulationError) and renumbers the rest in their order;
  // removed Boundary nodes leave their curve lists. Returns the old index of every kept node.
  std::vector<int> remove_nodes(NodeSet& nodes, const std::vector<char>& remove);

  // The exact shortcut for interior moves (see move_interior_node): an interior node whose exact
  // test accepted position p gets the budget clearance_from(p), a lower bound of the distance from p
  // to the boundary; each later move whose move_cost is below the remaining budget stays in the open
  // disc around p, which is inside the domain, so the exact test would accept it: it is skipped and
  // the cost is subtracted. The result is the same as always running the exact test.
  // Remaining budget of node i (0 when none; for the device-resident run's uploads).
  double clearance_budget(int node) const { return budget_[static_cast<std::size_t>(node)]; }
  // Lower bound of the distance from p to the boundary (0 on or near it); p must be inside.
  double clearance_from(Vec2 p) const;
  // Upper bound, with margins for rounding, of what a move by (ex, ey) ending at (px, py) uses of a
  // budget b: |e| (1 + 64 eps) + 8 eps (|px| + |py| + b), eps the precision's unit roundoff x 2.
  // The same formula in kernels/device_step.cl.
  static double move_cost(double ex, double ey, double px, double py, double budget);
  // The refresh rule (kernels/clearance.cl, clearance_refresh): a node known inside (budget > 0) whose
  // move by (ex, ey) to target costs less than clearance = clearance_from(target) stays inside without
  // the exact test, with the new budget clearance.
  static bool refresh_accepts(double ex, double ey, Vec2 target, double clearance);

 private:
  void insert_snapped(NodeSet& nodes, int node, Vec2 target);
  void move_boundary_nodes(NodeSet& nodes, const std::vector<double>& dx, const std::vector<double>& dy,
                           BoundaryCounts& counts);
  void move_interior_node(NodeSet& nodes, std::size_t i, Vec2 move, BoundaryCounts& counts,
                          const std::function<void()>* before_snap = nullptr);

  const GeometryTree& tree_;
  std::vector<std::vector<double>> arcs_;
  std::vector<Vec2> tangent_;   // per node
  std::vector<double> budget_;  // per node: remaining clearance budget (0: none, run the exact test)
};

}  // namespace pdmesh
