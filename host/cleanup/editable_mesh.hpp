// A triangle mesh the final cleanup can edit in place: triangle adjacency, per-vertex kind, curve
// and arc position, the local operations (flip, Lawson legalisation, vertex move, 1->3 and 2->4
// insertion, boundary edge split, edge collapse; in mesh_edits.cpp) and a journal so that a trial
// operation can be measured and undone (editable_mesh.cpp).
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "cleanup/measures.hpp"
#include "core/vec2.hpp"
#include "mesh/mesh.hpp"
#include "mesh/triangle_corners.hpp"

namespace pdmesh::cleanup {

class EditableMesh;

// An edge for EditableMesh::legalize(): its vertices a, b and a triangle t that has it (in either
// direction) when it is pushed.
struct EdgeRef {
  int a, b, t;
};

// The score quality(t) gives a live triangle, when not the default (the sine of its smallest angle):
// the cleanup in a metric scores triangles by their quality in the metric (metric_evaluator.hpp).
class TriangleScore {
 public:
  virtual ~TriangleScore() = default;
  virtual double score(const EditableMesh& mesh, int t) const = 0;
};

// Triangle t has counter-clockwise vertices v[t] and neighbours n[t], n[t][i] across the edge
// opposite v[t][i]; -1 there means the edge is on the domain boundary. In the constrained Delaunay
// mesh of a domain every constrained edge is such a boundary edge (even-odd rule), so "n == -1"
// and "constrained" are the same thing and no flip ever crosses the boundary. A dead triangle has
// v[t][0] == -1; a removed vertex has vt == -1. Slots are compacted only by to_mesh().
class EditableMesh {
 public:
  // mesh: a boundary-conforming triangulation with kinds (triangulate()'s output); curve_nodes:
  // per curve, its nodes in order (NodeSet::curve_nodes); arcs: their arc positions on the curve;
  // threads: at most this many threads find the triangles' neighbours (the same mesh on any number).
  EditableMesh(const Mesh& mesh, const std::vector<std::vector<int>>& curve_nodes,
               const std::vector<std::vector<double>>& arcs, std::size_t threads = 8);

  // Vertices.
  std::vector<Vec2> p;
  std::vector<NodeKind> kind;
  std::vector<int> curve;       // Boundary vertices: their curve; others -1
  std::vector<double> arc;      // Boundary vertices: arc position on their curve
  std::vector<int> prev, next;  // Boundary vertices: neighbours along the curve; others -1
  std::vector<int> vt;          // one incident triangle; -1 for a removed vertex
  // Triangles.
  std::vector<std::array<int, 3>> v;
  std::vector<std::array<int, 3>> n;

  int vertex_slots() const { return static_cast<int>(p.size()); }
  int triangle_slots() const { return static_cast<int>(v.size()); }
  bool alive(int t) const { return v[t][0] >= 0; }
  bool removed(int a) const { return gone_[a] != 0 || vt[a] < 0; }
  bool movable(int a) const { return kind[a] != NodeKind::Fixed; }
  double quality(int t) const;  // score_of(t, its points), or the score set_score() gave
  // The default score of triangle t with its vertices at x, y, z (v[t] in order): min_angle_sine,
  // less the angle at a sharp corner (set_sharp_corners) when t alone fills that corner.
  double score_of(int t, Vec2 x, Vec2 y, Vec2 z) const;
  // Marks the fixed vertices at a domain corner whose angle (the sum of their star's angles) is below
  // `degrees`. A triangle that alone fills such a corner has an angle there below any target, which no
  // edit changes; scored with it, it would stand for every star and region it is in, so no move or
  // repair near the corner could show a gain (the second row of a narrow inlet stayed below the target).
  // Such a triangle is scored by its other two angles; a corner shared by several triangles keeps
  // their own scores, so no edit gains by splitting the corner.
  void set_sharp_corners(double degrees);
  // The local index of the sharp corner triangle t alone fills, or -1.
  int sharp_corner_of(int t) const;
  // The triangle score of quality() and of the journal from now on (nullptr: min_angle_sine). Set it
  // before any transaction is opened; it must outlive the mesh's use.
  void set_score(const TriangleScore* score) { score_ = score; }
  double aspect(int t) const;  // aspect ratio R / (2 r) of triangle t
  // Boundary vertex a: the arc position of its neighbour along the curve before (side 0) or after
  // (side 1) it; a boundary vertex slides strictly between the two.
  double neighbour_arc(int a, int side) const;
  // The boundary edge opposite v[t][i]: its curve and the arc positions on it of v[t][next3(i)] and
  // v[t][prev3(i)]. False when it is not a boundary edge of a curve chain.
  bool boundary_edge_arcs(int t, int i, int& curve, double& arc_a, double& arc_b) const;

  // The triangles around vertex a, counter-clockwise; for a boundary vertex the open fan from the
  // triangle on its outgoing boundary edge to the one on its incoming boundary edge.
  void star(int a, std::vector<int>& out) const;
  // The vertices joined to a, in the order of star(a) (for a boundary vertex one more than the fan).
  void ring(int a, std::vector<int>& out) const;
  // The number of vertices joined to both a and b (the link condition of collapsing edge a-b).
  int common_neighbours(int a, int b) const;
  // Triangle t and local index i with edge a -> b counter-clockwise in t, opposite v[t][i];
  // {-1, -1} when there is no such edge.
  std::array<int, 2> find_edge(int a, int b) const;
  static int index_of(const std::array<int, 3>& tv, int value) { return pdmesh::index_of(tv, value); }

  // Edits. Each keeps the adjacency consistent; with a transaction open each saves what it changes.
  void flip(int t, int i);
  // Lawson flips of non-boundary edges whose opposite vertex lies strictly inside the circumcircle
  // (exact incircle), starting from the given edges and spreading to the edges of every flipped
  // quadrilateral. Restores the constrained Delaunay property around an edit. Each edge is found
  // through the triangle it names, not by a walk around a vertex: a node of an embedded constraint
  // has one open fan on each side of the cut, and a walk from vt[] sees only one of them.
  void legalize(std::vector<EdgeRef>& edges);
  // Whether legalize() given every edge of the live triangles would flip none: no edge between two
  // triangles has the opposite vertex strictly inside the circumcircle (exact incircle, the test
  // legalize() makes). Read-only, on at most `threads` threads.
  bool locally_delaunay(std::size_t threads) const;
  // Pushes the edges of a's link (the ones opposite a) for legalize().
  void push_link_edges(int a, std::vector<EdgeRef>& edges) const;
  void move(int a, Vec2 to, double new_arc);
  // The same for a caller that holds a's star (star(a)), as the smoother does.
  void move(int a, Vec2 to, double new_arc, const std::vector<int>& a_star);
  // Splits triangle t at `at`, which the caller has checked lies strictly inside it (1 -> 3).
  int insert_in_triangle(int t, Vec2 at);
  // Splits the interior edge opposite v[t][i] at `at` (2 -> 4); the caller checks that the four new
  // triangles are counter-clockwise (split_edge_valid).
  int split_edge(int t, int i, Vec2 at);
  bool split_edge_valid(int t, int i, Vec2 at) const;
  // Splits the boundary edge opposite v[t][i] (1 -> 2) at `at`, a point of curve `c` at arc position
  // `at_arc` between the edge's ends; the new node slides on that curve between them. The caller
  // checks that both new triangles are counter-clockwise.
  int split_boundary_edge(int t, int i, Vec2 at, double at_arc, int c);
  // Removes interior vertex a by collapsing edge a-b into b, which then moves to `to`. Returns false
  // (and changes nothing) when the link condition fails (the collapse would pinch the mesh); the
  // caller checks the orientation of b's new star afterwards.
  bool collapse(int a, int b, Vec2 to, double b_arc);
  // Removes boundary vertex a (one that slides on its curve) by collapsing the boundary edge a-b
  // into b, its neighbour along the curve, which stays where it is. Returns false (and changes
  // nothing) when the edge is not a boundary edge of a's chain, the triangle on it has another
  // boundary edge, the link condition fails, or a's other curve neighbour and b are both fixed (the
  // edge between them would have no sliding node to name its curve). The caller checks the
  // orientation of b's new star afterwards.
  bool collapse_boundary(int a, int b);
  // True when every triangle around a is strictly counter-clockwise (exact orient2d).
  bool star_valid(int a) const;

  // Transactions: begin(), edits, then commit() or rollback(). While open, the journal knows every
  // triangle whose vertices, neighbours or geometry changed, so the worst quality before and after
  // over exactly the affected region can be compared (the rest of the mesh is unchanged).
  void begin();
  bool in_transaction() const { return open_; }
  void commit();
  void rollback();
  double touched_min_before() const;  // +inf when nothing was touched
  double touched_min_after() const;
  // Sum of aspect ratios and number of those triangles, before and after (the cleanup keeps the
  // mesh's average aspect ratio from rising).
  double touched_aspect_before(int& count) const;
  double touched_aspect_after(int& count) const;
  // The live touched triangle with the lowest score now (-1 when none): where a compound trial's
  // second edit goes (topology_ops.cpp).
  int touched_worst_after() const;
  // How many of those triangles score below `limit`, before and after.
  int touched_below_before(double limit) const;
  int touched_below_after(double limit) const;
  // Vertices whose star changed (moved, a neighbour moved, flips, insertions, collapses) since the
  // last take_dirty(), which returns the flags (one per vertex slot) and clears them. A node whose
  // neighbourhood did not change makes the same proposal as last time, so sweeps skip it. Edits undone
  // by rollback() leave no mark.
  std::vector<std::uint8_t> take_dirty();
  bool dirty(int a) const { return dirty_[a] != 0; }
  // Epochs of the marks: every mark of vertex a (the ones take_dirty() returns) also records the
  // current epoch for it. A caller that keeps values computed from the mesh (the cleanup's kept
  // triangle scores) starts a new epoch after bringing them up to date; marked_in(a, e) then says
  // whether a's star changed since epoch e began, however many take_dirty() came between.
  std::uint32_t epoch() const { return epoch_; }
  void next_epoch() { ++epoch_; }
  bool marked_in(int a, std::uint32_t e) const { return marked_at_[a] >= e; }
  // The same for triangle slots: slot t is marked with the epoch whenever its vertices, their positions or
  // its neighbours change (outside a transaction, or in one committed), and a new slot with the epoch it
  // was made in. So a live triangle not marked in e has had the same points since e began. any_marked_in(e):
  // whether any vertex or triangle was marked since e began.
  bool triangle_marked_in(int t, std::uint32_t e) const { return tri_marked_at_[t] >= e; }
  bool any_marked_in(std::uint32_t e) const { return last_mark_ >= e; }
  // Marks triangle t's vertices as if their stars had changed, so the next sweeps try them again.
  void mark_changed(int t) { mark_dirty(t); }
  // Sweep moves that left vertex a where it was, with no mark of a since: one bit per kind of move
  // (the caller's numbering, at most 8). Every mark of a clears them, so a set bit says that a's star is
  // the one that move was tried on, and trying it again would make the same proposal and find the same.
  void set_unmoved(int a, std::uint8_t move) { unmoved_[a] |= move; }
  bool unmoved(int a, std::uint8_t move) const { return (unmoved_[a] & move) != 0; }
  // Vertices created by the open transaction (or since the last begin()).
  int first_new_vertex() const { return vert_size0_; }

  // The live triangles and vertices, renumbered in slot order; kinds kept. curve_nodes gets the
  // curve chains (boundary nodes are never removed; boundary splits add some), boundary_edges joins
  // their consecutive nodes as triangulate() does.
  Mesh to_mesh(const Mesh& original, std::vector<std::vector<int>>& curve_nodes, std::vector<int>& old_of_new) const;

 private:
  void touch_triangle(int t);
  void touch_vertex(int a);
  void touch_star(int a);
  void set_vt(int a, int t);
  void set_neighbour(int t, int old_neighbour, int new_neighbour);
  int new_triangle(std::array<int, 3> tv, std::array<int, 3> tn);
  int new_vertex(Vec2 at);

  struct SavedTriangle {
    int t;
    std::array<int, 3> v, n;
    double quality;  // before the transaction; +inf for a dead slot
    double aspect;   // aspect ratio before the transaction; 0 for a dead slot
  };
  struct SavedVertex {
    int a;
    Vec2 p;
    double arc;
    int vt;
    int prev, next;
    std::uint8_t gone;
  };
  const TriangleScore* score_ = nullptr;
  bool open_ = false;
  std::uint32_t stamp_ = 0;
  std::vector<std::uint32_t> tri_stamp_, vert_stamp_;
  std::vector<SavedTriangle> tri_log_;
  std::vector<SavedVertex> vert_log_;
  int tri_size0_ = 0, vert_size0_ = 0;
  std::vector<std::uint8_t> gone_;            // per vertex: removed by a collapse
  std::vector<std::uint8_t> sharp_;           // per vertex: a sharp corner (set_sharp_corners); empty: none
  std::vector<std::uint8_t> dirty_;           // per vertex: see take_dirty()
  std::vector<std::uint32_t> marked_at_;      // per vertex: the epoch of its last mark
  std::vector<std::uint8_t> unmoved_;         // per vertex: see set_unmoved()
  std::vector<std::uint32_t> tri_marked_at_;  // per triangle slot: the epoch of its last mark
  std::uint32_t epoch_ = 1;
  std::uint32_t last_mark_ = 1;  // the epoch of the last mark of any vertex or triangle
  void mark_vertex(int a) {
    dirty_[a] = 1;
    marked_at_[a] = epoch_;
    unmoved_[a] = 0;
    last_mark_ = epoch_;
  }
  void mark_dirty(int t);
  int sharp_corner_in(int t) const;  // sharp_corner_of() once some corner is sharp
  mutable std::vector<int> scratch_;
  std::vector<int> star_scratch_;
  // Per curve, its fixed nodes (ends and critical corners) in chain order with their arc positions.
  struct FixedEntry {
    int node;
    double arc;
  };
  std::vector<std::vector<FixedEntry>> fixed_on_curve_;
  // Boundary edges between two fixed nodes, by edge_key: their curve and the ends' arc positions.
  struct FixedEdge {
    int curve;
    int first;
    double first_arc, second_arc;
  };
  std::unordered_map<std::uint64_t, FixedEdge> fixed_edges_;
  static std::uint64_t edge_key(int a, int b) {
    const auto lo = static_cast<std::uint32_t>(a < b ? a : b), hi = static_cast<std::uint32_t>(a < b ? b : a);
    return (static_cast<std::uint64_t>(hi) << 32) | lo;
  }
};

// In the header: the sweeps score every triangle of every star they try, several times per move.
inline double EditableMesh::score_of(int t, Vec2 x, Vec2 y, Vec2 z) const {
  const int k = sharp_corner_of(t);
  return k < 0 ? min_angle_sine(x, y, z) : min_angle_sine_except(x, y, z, k);
}

inline int EditableMesh::sharp_corner_of(int t) const {
  if (sharp_.empty()) return -1;
  return sharp_corner_in(t);
}

inline double EditableMesh::quality(int t) const {
  return score_ != nullptr ? score_->score(*this, t) : score_of(t, p[v[t][0]], p[v[t][1]], p[v[t][2]]);
}

}  // namespace pdmesh::cleanup
