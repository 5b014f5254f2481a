// Gradation limit (Persson's gradient limiting) on the background quadtree's leaf corners:
// q(x) = min over sources y of q0(y) + g |x - y|, so that q(x) <= q(y) + g |x - y| for every pair.
#pragma once
#include <cstdint>
#include <utility>
#include <vector>

#include "core/vec2.hpp"

namespace pdmesh {

// A size constraint at a point that need not be a corner (tests; sizes given at points).
struct PointSource {
  Vec2 p;
  double q = 0.0;
};

// The corner graph of a quadtree: corners joined when they are corners of one leaf (its four sides
// and two diagonals). Leaves of different sizes meet at corners that lie on a larger leaf's side;
// those corners are joined through the smaller leaves.
class GradationGraph {
 public:
  // corners: every distinct leaf corner; leaf_corner: 4 indices into corners per leaf.
  GradationGraph(std::vector<Vec2> corners, const std::vector<std::int32_t>& leaf_corner);

  std::size_t size() const { return corners_.size(); }
  // From 2 x this many leaf corners the corners' leaf lists are sorted in two halves on two threads.
  static constexpr std::size_t kEntriesPerPart = 65536;
  const std::vector<Vec2>& corners() const { return corners_; }

  // The limited field. In: q0 at every corner. Out: q at every corner and its source: an index < size()
  // for a corner (whose q0 made the value), or size() + k for points[k]. The search is Dijkstra's in the
  // order of q, carrying each corner's source along the graph and measuring the Euclidean distance to it
  // (not the path length), so the result is the exact min over the sources that reach a corner through
  // its neighbours: the continuous formula at the corners, not an 8-neighbour stencil's approximation.
  // points[k] enters at the corners listed in point_corners[k] (those of the leaf holding it).
  // g <= 0: q = q0 and every corner is its own source.
  void limit(double g, const std::vector<double>& q0, std::vector<double>& q, std::vector<std::int32_t>& source,
             const std::vector<PointSource>& points = {},
             const std::vector<std::vector<std::int32_t>>& point_corners = {}) const;
  // The same sweep continued from a state (q, source: a previous result, extended to new corners with
  // any values not below the limit) from `seeds` only: after refinement only the new corners and
  // their neighbours can change anything. Sources index corners (< size()) or points as above.
  void relimit(double g, const std::vector<double>& q0, std::vector<double>& q, std::vector<std::int32_t>& source,
               const std::vector<std::int32_t>& seeds, const std::vector<PointSource>& points = {}) const;

 private:
  void sweep(double g, const std::vector<double>& q0, std::vector<double>& q, std::vector<std::int32_t>& source,
             const std::vector<std::int32_t>* seeds, const std::vector<PointSource>& points) const;

  std::vector<Vec2> corners_;
  // The graph without its edge list: each corner's leaves (CSR: corner -> positions 4 l + a in
  // leaf_corner_ where it is corner a of leaf l), whose other three corners are its neighbours. A
  // third of the entries of a neighbour list, written once per leaf corner.
  std::vector<std::int32_t> leaf_corner_;
  std::vector<std::int32_t> leaf_start_;
  std::vector<std::int32_t> leaf_of_;
};

namespace detail {
// The sweep's start entries (value, corner), given in ascending corner order, sorted as std::sort
// orders them: by value, then corner. Exposed for tests.
void sort_gradation_entries(std::vector<std::pair<double, std::int32_t>>& entries);
}  // namespace detail

}  // namespace pdmesh
