// Local topology operations of the final cleanup, tried on one bad triangle at a time: insert a node
// at its circumcentre (or, when that is outside the domain or too close to a node, at the frontal
// off-centre of its shortest edge: Rebay / Gmsh / MESH2D), collapse one of its edges (removing an
// interior node), split one of its interior edges at the midpoint, or split one of its boundary edges
// at the curve point halfway along the arc between its ends (JIGSAW splits boundary segments in
// narrow gaps the same way). Each trial is followed by a
// short local relaxation and Lawson flips, measured over exactly the triangles it touched and undone;
// the best trial is redone when it lifts the worst angle there by at least `gain`
// (JIGSAW keeps a change only when the local minimum quality rises by 1/300).
#pragma once
#include <array>
#include <functional>
#include <utility>
#include <vector>

#include "cleanup/editable_mesh.hpp"
#include "cleanup/smoothing.hpp"
#include "geometry/geometry.hpp"

namespace pdmesh::cleanup {

// Compound: two edits applied together (repair_compound); they may add and remove nodes.
enum class RepairKind { None, Insert, Collapse, Split, Compound };

struct TopologyOptions {
  double gain = 0.0035;  // required rise of the local minimum score (sine of the min angle)
  double target = 0.5;   // score of the target angle: a trial may not add triangles below it
  double enough = 1.0;   // a trial whose local minimum reaches this score is taken without trying the rest
  int relax_rounds = 2;
  bool split_boundary = true;  // may split boundary edges (a new node on the curve between the ends)
  // Size guards against h: an inserted node's shortest edge must be at least min_edge x h there (h no
  // more than the repaired triangle's shortest edge), and a collapse may not leave an edge longer
  // than max_edge x h (boundary edges aside: no collapse makes them), so that cleaning keeps the
  // spacing.
  double min_edge = 0.6;
  double max_edge = 1.5;  // hill-climbing rounds over the new node and its neighbours after an edit
  // Compound trials: a triangle the driver names (one below the target) that no single trial repairs gets every trial
  // followed by every trial on the worst triangle the first one left (see repair()).
  bool compound = true;
};

class TopologyOps {
 public:
  // h(p): the local edge length the mesh aims at (the spacing field scaled to the mesh, see cleanup.cpp).
  TopologyOps(EditableMesh& mesh, Smoother& smoother, const Geometry& geometry, std::function<double(Vec2)> h,
              TopologyOptions options);

  // Tries every operation on triangle t and applies the best one that helps; returns what it did.
  // When none helps and `compound` (the driver's choice: t is below the target),
  // tries pairs of operations (compound trials: the second on the worst triangle the first leaves),
  // which fix a defect no single edit can.
  RepairKind repair(int t, bool compound);
  // Compound trials made so far, and how many of them were applied.
  std::size_t compound_trials() const { return compound_trials_; }
  std::size_t compound_applied() const { return compound_applied_; }
  // Nodes the applied compound trials inserted and removed (their kinds say which).
  std::size_t compound_inserted() const { return compound_inserted_; }
  std::size_t compound_removed() const { return compound_removed_; }
  // The mesh's sum of aspect ratios and triangle count: an operation may not raise their average.
  // Set before a pass; repair() keeps them current.
  // Trials made so far (each an edit, a relaxation, a score and an undo: the unit of work).
  std::size_t trials() const { return trials_; }
  void set_aspect_totals(double sum, double count) {
    aspect_sum_ = sum;
    aspect_count_ = count;
  }

 private:
  struct Trial {
    RepairKind kind;
    std::function<bool()> apply;
    double shortest;  // shortest edge of the triangle it repairs (edges_fit's cap on h)
  };
  // The trials on triangle t of the mesh as it is now.
  void candidates(int t, std::vector<Trial>& out);
  // Applies first[k] and then the j-th trial on the worst triangle it touched (rebuilt on the mesh
  // after first[k], which is the same each time: edits are deterministic); false when either fails.
  bool apply_pair(const std::vector<Trial>& first, int k, int j, std::vector<Trial>& second);
  RepairKind repair_compound(const std::vector<Trial>& first);
  // True when the nodes the open transaction's edits made or merged keep the size guards.
  bool fits();
  // Keeps the open transaction (the chosen trial, redone) and updates the aspect-ratio totals.
  void commit_chosen();
  // One trial: applies the edit (false when it cannot be made) and relaxes; leaves the transaction open.
  bool insert_at(int t, Vec2 at);
  bool collapse_edge(int a, int b);
  bool split(int t, int i);
  bool split_boundary(int t, int i);
  void relax_around(int a);
  void settle(int a, bool inserted);
  int locate(int start, Vec2 at) const;
  Vec2 insertion_point(int t) const;
  // Score of the open transaction: the new local minimum, or -inf when it does not qualify.
  double score() const;
  bool edges_fit(int a, bool inserted, double shortest);
  bool boundary_edge(int a, int x) const;

  EditableMesh& mesh_;
  Smoother& smoother_;
  const Geometry& geometry_;
  std::function<double(Vec2)> h_;
  TopologyOptions options_;
  double aspect_sum_ = 0.0, aspect_count_ = 1.0;
  std::size_t trials_ = 0;
  std::size_t compound_trials_ = 0, compound_applied_ = 0, compound_inserted_ = 0, compound_removed_ = 0;
  double shortest_ = 0.0;  // shortest edge of the triangle being repaired
  // The nodes the open transaction's edits inserted or merged into, whether each was inserted, and
  // the repaired triangle's shortest edge then (for edges_fit); cleared by each trial.
  struct Fit {
    int node;
    bool inserted;
    double shortest;
  };
  std::vector<Fit> fit_;
  std::vector<int> ring_, ring2_;
  std::vector<EdgeRef> edges_;
};

}  // namespace pdmesh::cleanup
