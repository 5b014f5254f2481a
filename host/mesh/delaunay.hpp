// Incremental Delaunay triangulation (Hilbert-ordered insertion, remembering walk, Lawson flips
// from an explicit stack) inside a super-triangle; the data structure the constraint step edits.
#pragma once
#include <array>
#include <cstdint>
#include <unordered_set>
#include <vector>

#include "core/vec2.hpp"

namespace pdmesh {

// Triangle t has vertices v[t] in counter-clockwise order and neighbours n[t], where n[t][i] is
// the triangle across the edge opposite v[t][i] (-1 outside the super-triangle).
// Vertices are stored in Hilbert order (so neighbouring triangles touch nearby memory):
// vertex k is input point input_index[k], input point i is vertex vertex_of[i]; the three
// super-triangle vertices follow the input_count input points. The super-triangle is finite (a box 100 times the
// input's extent), so the triangles kept after removing it are Delaunay, but near the convex hull a few hull edges may
// be missing; domain meshing constrains its boundary, so that never matters there.
class Triangulation {
 public:
  // Throws InputError for fewer than 3 points, non-finite coordinates or a duplicate point
  // (naming both indices and the coordinates), GeometryError when all points are collinear.
  explicit Triangulation(const std::vector<Vec2>& input);

  std::vector<Vec2> points;           // input points in Hilbert order, then the 3 super vertices
  std::vector<int> input_index;       // vertex -> input point index
  std::vector<int> vertex_of;         // input point index -> vertex
  std::vector<std::array<int, 3>> v;  // triangle vertices, counter-clockwise
  std::vector<std::array<int, 3>> n;  // neighbours, n[t][i] opposite v[t][i]
  std::vector<int> vertex_triangle;   // one triangle incident to each vertex
  int input_count = 0;

  bool is_super(int vertex) const { return vertex >= input_count; }
  static std::uint64_t edge_key(int a, int b);
  // Marks the edge a-b (either direction) as one Lawson must not flip.
  void constrain(int a, int b);
  // Most vertices are on no constrained edge: their flag answers without hashing the edge (every
  // convergence check asks for each edge of its ~80k, in make_delaunay and the parity fill).
  bool is_constrained(int a, int b) const {
    return !constrained_.empty() && on_constraint_[static_cast<std::size_t>(a)] &&
           on_constraint_[static_cast<std::size_t>(b)] && constrained_.count(edge_key(a, b)) > 0;
  }

  // Flips the edge opposite v[t][i] (the quadrilateral must be strictly convex); see the diagram
  // in delaunay.cpp for the names. Afterwards t = (p, a, q) and the old neighbour u = (q, b, p).
  void flip(int t, int i);
  // The triangle t and index i with edge a-b opposite v[t][i] and a -> b counter-clockwise in t,
  // found by rotating around a; {-1, -1} when no such edge exists.
  std::array<int, 2> find_edge(int a, int b) const;
  // Triangles around vertex a, counter-clockwise, starting at vertex_triangle[a].
  std::vector<int> triangles_around(int a) const;
  // Restores the (constrained) Delaunay property by Lawson flips of every non-constrained edge,
  // driven by an explicit stack. Used after edge recovery. Returns the number of flips: 0 on a
  // triangulation just built, which the incremental insertion leaves Delaunay under the same exact
  // incircle test (tests/test_delaunay.cpp checks it; recover_edges relies on it).
  int make_delaunay();
  // Inserts the points input[input_count..) (the points before them must be the ones the triangulation
  // holds) as the construction inserts its own: each located by the walk from the last one's triangle,
  // split in and legalized under the same exact predicates; they become input points input_count.. (the
  // super vertices follow them). Returns false, changing nothing, when the super-triangle of all of
  // `input` is not this one (a new point outside the box of the points held), when a new coordinate is
  // not finite or when edges are constrained. Throws InputError for a new point on a point held; the
  // triangulation is then unusable. The result is a Delaunay triangulation of all the points; it is
  // the one a construction from `input` makes, as far as inner_triangles goes, when
  // unique_inner_triangles().
  bool add_points(const std::vector<Vec2>& input);
  // Whether every (constrained) Delaunay triangulation of the points (with the super vertices and the
  // constrained edges) has this one's
  // triangles among the input points (inner_triangles, as a set), whatever order of insertion made it:
  // it is Delaunay (constrained Delaunay: constrained edges are not judged), and wherever four or more
  // points are cocircular (an edge whose far vertex is on
  // the circumcircle) the polygon they make has at most two input points and no diagonal between two
  // of them, so that every triangle of every triangulation of it has a super vertex. (Two super
  // vertices are cocircular with two hull points placed symmetrically about the box's centre: such
  // ties are common and harmless. A grid's cells are not.)
  bool unique_inner_triangles() const;
  // Triangles not touching the super-triangle, in input point indices (unconstrained use).
  std::vector<std::array<int, 3>> inner_triangles() const;

 private:
  void build();
  int locate(Vec2 p, int start) const;
  void insert(int vertex, int t);
  void legalize(std::vector<std::array<int, 2>>& stack);
  void replace_neighbour(int t, int old_neighbour, int new_neighbour);
  std::vector<std::array<int, 2>> flip_stack_;     // reused by every insertion
  std::unordered_set<std::uint64_t> constrained_;  // edge_key of edges Lawson must not flip
  std::vector<char> on_constraint_;                // per vertex: an end of a constrained edge
};

// Delaunay triangles of the points (without constraints); see Triangulation for the hull caveat.
std::vector<std::array<int, 3>> delaunay_triangles(const std::vector<Vec2>& points);

}  // namespace pdmesh
