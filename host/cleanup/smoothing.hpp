// Hill-climbing node smoothing for the final cleanup: each move proposes the ODT point (area-weighted
// circumcentres of the adjacent triangles, Chen & Holst; optimesh's odt-fixed-point), caps the step
// at a fraction of the smallest adjacent inradius (optimesh), slides boundary nodes along their own
// curve between their curve neighbours, and is kept only when no adjacent triangle inverts and the
// adjacent minimum angle does not drop (JIGSAW / MESH2D hill-climbing). Lawson flips follow.
#pragma once
#include <array>
#include <functional>
#include <utility>
#include <vector>

#include "cleanup/editable_mesh.hpp"
#include "geometry/geometry.hpp"

namespace pdmesh::cleanup {

// What the last accepted move gained on its star: the rise of the smallest score (sine of the smallest
// angle), the drop of the sum of aspect ratios (both measured before its Lawson flips) and the star's size.
struct MoveGain {
  double min_rise = 0.0;
  double aspect_drop = 0.0;
  int triangles = 0;
};

// Counts an accepted move into a record of the sweeps' moves (CleanupIteration, SweepTally: moves,
// small_moves, aspect_drop, small_aspect_drop); a small move lowered its star's mean aspect ratio by
// less than 1e-4.
template <class Record>
void count_move(Record& r, const MoveGain& g) {
  ++r.moves;
  r.aspect_drop += g.aspect_drop;
  if (g.aspect_drop < 1e-4 * g.triangles) {
    ++r.small_moves;
    r.small_aspect_drop += g.aspect_drop;
  }
}

// Adds one record of the sweeps' moves to another.
template <class Record, class From>
void add_moves(Record& r, const From& f) {
  r.moves += f.moves;
  r.small_moves += f.small_moves;
  r.aspect_drop += f.aspect_drop;
  r.small_aspect_drop += f.small_aspect_drop;
}

class Smoother {
 public:
  // step_cap: the largest step as a fraction of the smallest inradius of the adjacent triangles.
  Smoother(EditableMesh& mesh, const Geometry& geometry, double step_cap);

  // One hill-climbing move of vertex a (Fixed and removed vertices never move). Returns true when
  // it moved; the edges around it are then made constrained Delaunay again by Lawson flips.
  bool relax(int a);
  // Gradient move: a step that raises the smallest angle of a's worst adjacent triangle, for
  // vertices whose ODT point does not help (same guards as relax).
  bool climb(int a);
  // relax() and climb() for a caller that has put a's star (EditableMesh::star(a)) in star_buffer(),
  // with no edit since: they use it rather than walk the star again (the strip sweeps' test walks it).
  bool relax_with_star(int a) { return relax(a, true); }
  bool climb_with_star(int a) { return climb(a, true); }
  std::vector<int>& star_buffer() { return fan_; }
  const MoveGain& last_gain() const { return last_gain_; }
  // The least gain a sweep move must make (a trial's relaxation takes any): a rise of the star's
  // smallest score above min_rise, or a drop of its aspect-ratio sum above aspect_drop per star
  // triangle. 0 and 0: any strict improvement.
  void set_sweep_gain(double min_rise, double aspect_drop) {
    min_rise_ = min_rise;
    aspect_drop_ = aspect_drop;
  }
  // Lifting climbs: a climb of a vertex whose star's worst triangle scores below `score` (the
  // target's or a little above) and is one `stuck` names (one no topology change could repair, or one
  // no topology pass will try again) is judged by the star's smallest score alone, so it may raise the star's
  // aspect-ratio sum. A tall triangle whose apex is a far-field node above a finer interior row is lifted only by
  // moving a row node so that its nearly equilateral neighbours stretch, which raises their aspect ratios more than it
  // lowers the bad one's (docs/cleanup.md, "Lifting climbs"). Off until set.
  void set_lift(double score, std::function<bool(int)> stuck) {
    lift_below_ = score;
    stuck_ = std::move(stuck);
  }
  // Deferring (the strip sweeps of strip_sweeps.hpp): a move that would need Lawson flips is not
  // made; relax() and climb() return false and deferred() is true until the next call. With it on, a
  // move writes only the vertex's position and arc and its star's dirty marks, never the topology.
  void set_defer_flips(bool on) { defer_flips_ = on; }
  bool deferred() const { return deferred_; }

 private:
  // star_known: fan_ holds a's star already.
  bool relax(int a, bool star_known);
  bool climb(int a, bool star_known);
  // lift: judged by the star's smallest score alone (set_lift).
  bool try_move(int a, Vec2 displacement, double old_min, double old_sum, bool lift = false);
  Vec2 on_curve(int a, Vec2 candidate, double& new_arc) const;
  Vec2 score_gradient(int t, int a, double h) const;
  bool flips_needed(int a, Vec2 to) const;
  // A triangle of the star of the vertex try_move() moves: its corner k holds the vertex, x, y, z are
  // its points before the move, `opposite` the squared length of the side opposite the vertex, sharp
  // EditableMesh::sharp_corner_of(t), opposite_length that side's length.
  struct StarEdge {
    int k, sharp;
    Vec2 x, y, z;
    double opposite, opposite_length;
    double twice_area, score, aspect, inradius;  // before the move
  };
  static double aspect_at(const StarEdge& e, const double* sides, double twice_area);
  // star_edges_ for a's star in fan_, in its order (relax() and climb() measure the star with it).
  void set_star_edges(int a);
  double score_at(const StarEdge& e, Vec2 x, Vec2 y, Vec2 z, double twice_area, double* sides) const;
  // Star triangle j's score with the vertex at `to`.
  double score_at(std::size_t j, Vec2 to) const;

  EditableMesh& mesh_;
  const Geometry& geometry_;
  double step_cap_;
  std::vector<int> fan_;
  std::vector<EdgeRef> edges_;
  std::vector<StarEdge> star_edges_;  // set_star_edges()
  MoveGain last_gain_;
  double min_rise_ = 0.0, aspect_drop_ = 0.0;
  double lift_below_ = -1.0;
  std::function<bool(int)> stuck_;
  bool defer_flips_ = false, deferred_ = false;
};

}  // namespace pdmesh::cleanup
