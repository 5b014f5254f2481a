// The local operations of the cleanup in a metric (metric_cleanup.hpp), on an EditableMesh scored by
// a MetricEvaluator (so quality() and the journal's minima are the metric quality Q): edge splits
// where the metric length L > √2 (metric_split.cpp), edge collapses where L < collapse_below
// (metric_collapse.cpp), flips that raise the smallest Q of their quadrilateral (metric_flips.cpp)
// and node smoothing and climbing in the metric (metric_smoothing.cpp). Every edit keeps every triangle strictly
// counter-clockwise in physical space by the exact orient2d; fixed nodes never move or go; boundary
// nodes move and are placed only on their own curve.
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "cleanup/editable_mesh.hpp"
#include "cleanup/metric_evaluator.hpp"
#include "geometry/geometry.hpp"

namespace pdmesh::cleanup {

// The unit-mesh window of metric lengths the splits and collapses aim at.
inline const double kMetricLong = 1.4142135623730951;
inline const double kMetricShort = 0.7071067811865476;

struct MetricOpsOptions {
  bool split_boundary = true;  // boundary edges may be split by a new node on their curve
  // A split or collapse is kept when the smallest Q of the triangles it touched is at least
  // keep_ratio times what it was, or at least keep_floor.
  double keep_ratio = 0.5;
  double keep_floor = 0.3;
  // Edges shorter than this (metric length) are collapsed: above the window's 1/√2, so that the
  // element count comes near the unit mesh's 4C/√3 rather than above it (a mesh of edges between
  // 1/√2 and 1 has more triangles than the unit mesh), yet a collapse may not leave an edge at the
  // node it keeps longer than collapse_max_length or than the longest edge of the two ends before.
  double collapse_below = 0.8;
  double collapse_max_length = kMetricLong;
  // Smoothing: step lengths tried per move (the proposal, then halved).
  int line_search = 4;
  // The climb moves a node whose ball's smallest Q is below this whenever that minimum rises, even
  // when edges of its ball leave the window [1/√2, √2]; above it no move takes an edge out of the
  // window. Above keep_floor, so that the worst triangles are lifted clear of it.
  double repair_below = 0.35;
};

struct MetricOpsCounts {
  std::size_t splits = 0, boundary_splits = 0;
  std::size_t collapses = 0, boundary_collapses = 0;
  std::size_t flips = 0;
  std::size_t moves = 0;
};

class MetricOps {
 public:
  MetricOps(EditableMesh& mesh, const MetricEvaluator& metric, const Geometry& geometry, MetricOpsOptions options);

  // One pass over the edges longer than √2, longest first. Returns the splits made.
  std::size_t split_long();
  // One pass over the edges shorter than collapse_below, shortest first. Returns the collapses made.
  std::size_t collapse_short();
  // Flips until no interior edge's flip raises the smallest Q of its two triangles (bounded by
  // max_rounds passes over the edges). Returns the flips made.
  std::size_t flip_all(int max_rounds);
  // One smoothing sweep over the movable vertices. Returns the moves made.
  std::size_t smooth();
  // One sweep over the nodes of the triangles whose Q is below `below`, each moved up the gradient
  // of its ball's worst Q. Returns the moves made.
  std::size_t climb(double below);
  const MetricOpsCounts& counts() const { return counts_; }

 private:
  struct Edge {
    double length;
    int a, b;
  };
  // The length splits and collapses go by for the edge opposite v[t][i]: its metric length, or for a
  // boundary edge of a curve chain the longer of that and the curve's metric length between its ends
  // (spacing/curve_metric_length), which sees a metric that varies along the curve between them.
  double measure(int t, int i) const;
  // The same for the edge a-b (its metric length when it is not an edge of the mesh).
  double measure_between(int a, int b) const;
  // The edges (each once) whose measure is above `above` or below `below`.
  std::vector<Edge> edges_where(double above, double below) const;
  bool keep_edit() const;
  bool split_edge(int a, int b);
  bool collapse_edge(int a, int b);
  // The longest metric edge at a, leaving out the edge to `skip` (-1: none).
  double longest_edge(int a, int skip);
  // Moves boundary node a along its curve to the metric middle of its curve neighbours.
  bool centre_on_curve(int a);
  bool flip_if_better(int t, int i);
  bool move_vertex(int a, bool climb);
  Vec2 proposal(int a) const;
  Vec2 ascent(int a) const;
  // repair: the window guard yields to a rise of the ball's smallest Q (repair_below).
  bool try_position(int a, Vec2 to, double to_arc, double old_min, double old_error, int old_outside, bool repair);

  // The nodes whose ball changed since the smoothing (climb) last tried them: the editable mesh's
  // dirty marks, taken by absorb_changes() before each sweep.
  void absorb_changes();
  bool pending(std::vector<std::uint8_t>& marks, int a) const;  // and clears the mark

  EditableMesh& m_;
  const MetricEvaluator& metric_;
  const Geometry& geometry_;
  MetricOpsOptions options_;
  MetricOpsCounts counts_;
  std::vector<int> fan_, ring_;
  std::vector<std::uint8_t> smooth_pending_, climb_pending_;
  // The epoch the last flip pass began (0: none yet, every edge is tested).
  std::uint32_t flip_pass_epoch_ = 0;
};

}  // namespace pdmesh::cleanup
