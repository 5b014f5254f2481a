// Constrained edge recovery by flipping crossed edges, and parity flood fill removing the
// triangles outside the domain and in holes.
#include "mesh/constrain.hpp"

#include <fmt/format.h>

#include <deque>

#include "core/interrupt.hpp"
#include "core/errors.hpp"
#include "core/predicates.hpp"
#include "mesh/triangle_corners.hpp"

namespace pdmesh {
namespace {

// Index of the vertex of a triangle that is neither x nor y.
int third_index(const std::array<int, 3>& tv, int x, int y) {
  return (tv[0] != x && tv[0] != y) ? 0 : ((tv[1] != x && tv[1] != y) ? 1 : 2);
}

std::string describe(const Triangulation& tri, const ConstrainedEdge& e) {
  const Vec2 pa = tri.points[e.a], pb = tri.points[e.b];
  std::string curve = e.curve >= 0 ? fmt::format(" of curve {}", e.curve) : std::string();
  return fmt::format("edge{} from point {} ({}, {}) to point {} ({}, {})", curve, tri.input_index[e.a], pa.x, pa.y,
                     tri.input_index[e.b], pb.x, pb.y);
}

[[noreturn]] void throw_point_on_edge(const Triangulation& tri, const ConstrainedEdge& e, int point) {
  const Vec2 p = tri.points[point];
  throw GeometryError(
      fmt::format("point {} ({}, {}) lies inside boundary {}; boundary points may only be edge end points",
                  tri.input_index[point], p.x, p.y, describe(tri, e)));
}

// The crossed edges of the triangulation along segment a-b, as (right, left) vertex pairs,
// found by walking from a towards b.
std::vector<std::array<int, 2>> crossed_edges(const Triangulation& tri, const ConstrainedEdge& e) {
  const auto& P = tri.points;
  const Vec2 pa = P[e.a], pb = P[e.b];
  auto on_segment_side = [&](int c) {  // c collinear with a-b and on b's side of a: inside a-b
    if (tri.is_super(c) || orient2d(pa, pb, P[c]) != 0.0) return false;
    return dot(P[c] - pa, pb - pa) > 0.0;  // signs of collinear differences are exact
  };
  int t = -1, right = -1, left = -1;
  for (int f : tri.triangles_around(e.a)) {
    const int k = index_of(tri.v[f], e.a);
    const int c = tri.v[f][(k + 1) % 3], d = tri.v[f][(k + 2) % 3];
    if (on_segment_side(c)) throw_point_on_edge(tri, e, c);
    if (orient2d(pa, P[c], pb) > 0.0 && orient2d(pa, P[d], pb) < 0.0) {
      t = f;
      right = c;
      left = d;
    }
  }
  if (t < 0) throw GeometryError(fmt::format("cannot start recovery of boundary {}", describe(tri, e)));
  std::vector<std::array<int, 2>> crossed;
  for (;;) {
    if (tri.is_constrained(right, left)) {
      throw GeometryError(fmt::format(
          "boundary {} crosses the boundary edge from point {} ({}, {}) to point {} ({}, {})", describe(tri, e),
          tri.input_index[right], P[right].x, P[right].y, tri.input_index[left], P[left].x, P[left].y));
    }
    crossed.push_back({right, left});
    const int u = tri.n[t][third_index(tri.v[t], right, left)];
    const int opposite = tri.v[u][third_index(tri.v[u], right, left)];
    if (opposite == e.b) break;
    const double side = orient2d(pa, pb, P[opposite]);
    if (side == 0.0) throw_point_on_edge(tri, e, opposite);
    (side < 0.0 ? right : left) = opposite;
    t = u;
  }
  return crossed;
}

// Sloan's recovery: flip crossed edges whose quadrilateral is strictly convex; a new edge that
// still crosses a-b goes back into the queue. Terminates (Sloan 1993); the guard only turns a
// bug into an error instead of a hang.
// Returns whether it flipped anything.
bool recover_edge(Triangulation& tri, const ConstrainedEdge& e) {
  if (e.a == e.b) throw GeometryError(fmt::format("boundary {} has zero length", describe(tri, e)));
  if (tri.find_edge(e.a, e.b)[0] >= 0 || tri.find_edge(e.b, e.a)[0] >= 0) {
    tri.constrain(e.a, e.b);
    return false;
  }
  const auto& P = tri.points;
  const auto crossed = crossed_edges(tri, e);
  std::deque<std::array<int, 2>> queue(crossed.begin(), crossed.end());
  const std::size_t limit = 1000 + 100 * crossed.size() * crossed.size();
  for (std::size_t step = 0; !queue.empty(); ++step) {
    if (step > limit) throw GeometryError(fmt::format("recovery of boundary {} did not terminate", describe(tri, e)));
    const auto [c, d] = queue.front();
    queue.pop_front();
    auto found = tri.find_edge(c, d);
    if (found[0] < 0) found = tri.find_edge(d, c);
    const auto [t, i] = found;
    const int u = tri.n[t][i];
    const int p = tri.v[t][i], a = tri.v[t][(i + 1) % 3], b = tri.v[t][(i + 2) % 3];
    const int q = tri.v[u][index_of(tri.n[u], t)];
    if (orient2d(P[p], P[a], P[q]) > 0.0 && orient2d(P[q], P[b], P[p]) > 0.0) {
      tri.flip(t, i);
      if (segments_cross_properly(P[p], P[q], P[e.a], P[e.b])) queue.push_back({p, q});
    } else {
      queue.push_back({c, d});
    }
  }
  tri.constrain(e.a, e.b);
  return true;
}

}  // namespace

void recover_edges(Triangulation& tri, const std::vector<ConstrainedEdge>& edges) {
  for (const auto& e : edges) {
    if (e.a < 0 || e.b < 0 || e.a >= tri.input_count || e.b >= tri.input_count)
      throw InputError(fmt::format("boundary edge {}-{} names a point outside 0..{}", e.a, e.b, tri.input_count - 1));
  }
  // Work in the triangulation's vertex numbering; messages translate back to input indices.
  bool flipped = false;
  InterruptPoll poll(1024);
  for (const auto& e : edges) {
    poll.tick();
    flipped |= recover_edge(tri, {tri.vertex_of[e.a], tri.vertex_of[e.b], e.curve});
  }
  // Without a recovery flip the triangulation is the incremental one, already Delaunay under the
  // same exact test: the full Lawson pass (an incircle test and an edge search for each of its ~3n
  // edges, a fifth of a convergence check's triangulation) would flip nothing.
  if (flipped) tri.make_delaunay();
}

std::vector<std::array<int, 3>> inside_triangles(Triangulation&& tri,
                                                 const std::unordered_set<std::uint64_t>& open_edges) {
  const int count = static_cast<int>(tri.v.size());
  // The fill reads neither map from points to vertices nor the vertex-to-triangle map: freed before
  // the layers are made (a convergence check's triangulation is the largest moment of a run).
  std::vector<int>().swap(tri.vertex_of);
  std::vector<int>().swap(tri.vertex_triangle);
  // Per triangle the parity of its layer (only the parity decides inside), kUnreached until reached:
  // one byte per triangle.
  constexpr std::uint8_t kUnreached = 0xff;
  std::vector<std::uint8_t> layer(count, kUnreached);
  std::vector<int> current, stack, next;
  for (int t = 0; t < count; ++t) {
    const auto& tv = tri.v[t];
    if (tri.is_super(tv[0]) || tri.is_super(tv[1]) || tri.is_super(tv[2])) {
      layer[t] = 0;
      current.push_back(t);
    }
  }
  // Layer k: reachable from layer k-1 by crossing exactly one more constrained edge.
  for (int depth = 0; !current.empty(); ++depth) {
    stack = current;
    while (!stack.empty()) {
      const int t = stack.back();
      stack.pop_back();
      for (int i = 0; i < 3; ++i) {
        const int u = tri.n[t][i];
        if (u < 0 || layer[u] != kUnreached) continue;
        const int a = tri.v[t][(i + 1) % 3], b = tri.v[t][(i + 2) % 3];
        if (tri.is_constrained(a, b) && (open_edges.empty() || !open_edges.count(Triangulation::edge_key(
                                                                   tri.input_index[a], tri.input_index[b])))) {
          next.push_back(u);
        } else {
          layer[u] = static_cast<std::uint8_t>(depth & 1);
          stack.push_back(u);
        }
      }
    }
    current.clear();
    for (int u : next) {
      if (layer[u] == kUnreached) {
        layer[u] = static_cast<std::uint8_t>((depth + 1) & 1);
        current.push_back(u);
      }
    }
    next.clear();
  }
  // The inside triangles are written over the triangulation's own list, in order (the written count
  // never passes t), after the arrays the fill needed are freed: no second triangle list is held
  // beside the triangulation (a convergence check's largest moment).
  std::vector<std::array<int, 3>>().swap(tri.n);
  std::vector<Vec2>().swap(tri.points);
  std::vector<std::array<int, 3>> inside = std::move(tri.v);
  std::size_t written = 0;
  for (int t = 0; t < count; ++t)
    if (layer[t] == 1) {
      const auto tv = inside[t];
      inside[written++] = {tri.input_index[tv[0]], tri.input_index[tv[1]], tri.input_index[tv[2]]};
    }
  inside.resize(written);
  return inside;
}

}  // namespace pdmesh
