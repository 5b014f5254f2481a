// Incremental Delaunay triangulation: Hilbert-ordered insertion, remembering visibility walk,
// Lawson flips from an explicit stack, all decisions by the exact predicates.
#include "mesh/delaunay.hpp"

#include <fmt/format.h>

#include <cmath>
#include <cstring>

#include "core/interrupt.hpp"
#include "core/errors.hpp"
#include "core/predicates.hpp"
#include "geometry/hilbert.hpp"
#include "mesh/triangle_corners.hpp"

namespace pdmesh {
namespace {

void check_input(const std::vector<Vec2>& pts) {
  if (pts.size() < 3) throw InputError(fmt::format("triangulation needs at least 3 points, got {}", pts.size()));
  if (pts.size() > (1u << 29)) throw LimitError(fmt::format("triangulation of {} points is too large", pts.size()));
  for (std::size_t i = 0; i < pts.size(); ++i) {
    if (!std::isfinite(pts[i].x) || !std::isfinite(pts[i].y))
      throw InputError(fmt::format("point {} has a non-finite coordinate ({}, {})", i, pts[i].x, pts[i].y));
  }
  std::size_t second = 1;
  while (second < pts.size() && pts[second] == pts[0]) ++second;
  if (second == pts.size())
    throw InputError(fmt::format("duplicate point: points 0 and 1 are both at ({}, {})", pts[0].x, pts[0].y));
  for (std::size_t i = second + 1; i < pts.size(); ++i) {
    if (orient2d(pts[0], pts[second], pts[i]) != 0.0) return;
  }
  throw GeometryError(
      fmt::format("all {} points are collinear (on the line through ({}, {}) and ({}, {})): "
                  "no triangle can be formed",
                  pts.size(), pts[0].x, pts[0].y, pts[second].x, pts[second].y));
}

// The super-triangle's vertices for input points with bounding box `box`.
std::array<Vec2, 3> super_vertices(const Box& box) {
  const Vec2 c = box.centre();
  const double m = std::max(box.width(), box.height());
  // Far enough that the input's hull is (nearly always) reproduced, near enough that the
  // predicates rarely leave their floating-point filter.
  const double s = 100.0 * m;
  return {Vec2{c.x - 2 * s, c.y - s}, Vec2{c.x + 2 * s, c.y - s}, Vec2{c.x, c.y + 2 * s}};
}

}  // namespace

std::uint64_t Triangulation::edge_key(int a, int b) {
  const auto lo = static_cast<std::uint32_t>(a < b ? a : b), hi = static_cast<std::uint32_t>(a < b ? b : a);
  return (static_cast<std::uint64_t>(hi) << 32) | lo;
}

Triangulation::Triangulation(const std::vector<Vec2>& input) {
  check_input(input);
  input_count = static_cast<int>(input.size());
  input_index = hilbert_order(input);
  vertex_of.resize(input.size());
  points.reserve(input.size() + 3);
  for (int k = 0; k < input_count; ++k) {
    points.push_back(input[input_index[k]]);
    vertex_of[input_index[k]] = k;
  }
  build();
}

void Triangulation::build() {
  Box box;
  for (const Vec2& p : points) box.add(p);
  for (const Vec2& p : super_vertices(box)) points.push_back(p);
  const std::size_t triangle_estimate = 2 * points.size() + 1;
  v.reserve(triangle_estimate);
  n.reserve(triangle_estimate);
  v.push_back({input_count, input_count + 1, input_count + 2});
  n.push_back({-1, -1, -1});

  int last = 0;
  for (int vertex = 0; vertex < input_count; ++vertex) {
    if ((vertex & 8191) == 0) check_interrupt();
    last = locate(points[vertex], last);
    insert(vertex, last);
  }
  vertex_triangle.assign(points.size(), -1);
  for (int t = 0; t < static_cast<int>(v.size()); ++t)
    for (int vertex : v[t]) vertex_triangle[vertex] = t;
}

bool Triangulation::add_points(const std::vector<Vec2>& input) {
  const auto m = static_cast<std::size_t>(input_count);
  if (input.size() < m || !constrained_.empty() || points.size() != m + 3) return false;
  if (input.size() == m) return true;
  if (input.size() > (1u << 29)) throw LimitError(fmt::format("triangulation of {} points is too large", input.size()));
  // The super-triangle a construction from all of `input` would make: the same, or no insertion.
  Box box;
  for (std::size_t k = 0; k < m; ++k) box.add(points[k]);
  for (std::size_t i = m; i < input.size(); ++i) {
    if (!std::isfinite(input[i].x) || !std::isfinite(input[i].y)) return false;
    box.add(input[i]);
  }
  const std::array<Vec2, 3> super = super_vertices(box);
  if (std::memcmp(super.data(), points.data() + m, sizeof(super)) != 0) return false;
  // The super vertices move behind the new input vertices.
  const int added = static_cast<int>(input.size() - m);
  for (auto& tv : v)
    for (int& vertex : tv)
      if (vertex >= input_count) vertex += added;
  points.resize(m);
  for (std::size_t i = m; i < input.size(); ++i) {
    points.push_back(input[i]);
    input_index.push_back(static_cast<int>(i));
    vertex_of.push_back(static_cast<int>(i));
  }
  for (const Vec2& p : super) points.push_back(p);
  input_count = static_cast<int>(input.size());
  // As in build: each new vertex located by the walk from the last one's triangle, then inserted.
  vertex_triangle.clear();
  int last = 0;
  for (int vertex = static_cast<int>(m); vertex < input_count; ++vertex) {
    last = locate(points[vertex], last);
    insert(vertex, last);
  }
  vertex_triangle.assign(points.size(), -1);
  for (int t = 0; t < static_cast<int>(v.size()); ++t)
    for (int vertex : v[t]) vertex_triangle[vertex] = t;
  return true;
}

bool Triangulation::unique_inner_triangles() const {
  // The edges whose far vertex lies on the circumcircle (a tie: either diagonal is Delaunay). Each
  // group of triangles joined by ties triangulates one polygon of cocircular points, and every
  // triangulation of it is Delaunay; elsewhere every triangulation has these triangles.
  std::vector<std::array<int, 2>> ties;
  for (int t = 0; t < static_cast<int>(v.size()); ++t) {
    const auto& tv = v[t];
    for (int i = 0; i < 3; ++i) {
      const int u = n[t][i];
      if (u < t) continue;  // each edge between two triangles once (u < 0: the super-triangle's sides)
      if (is_constrained(tv[next3(i)], tv[prev3(i)])) continue;  // kept whatever the circle says
      const int q = v[u][index_of(n[u], t)];
      const double side = incircle(points[tv[i]], points[tv[next3(i)]], points[tv[prev3(i)]], points[q]);
      if (side > 0.0) return false;  // not Delaunay
      if (side == 0.0) {
        // A diagonal between two input points: another triangulation of the polygon lacks it.
        if (!is_super(tv[next3(i)]) && !is_super(tv[prev3(i)])) return false;
        ties.push_back({t, u});
      }
    }
  }
  if (ties.empty()) return true;
  // A polygon with at most two input points has a super vertex in every triangle of every
  // triangulation: none of its triangles is an input triangle, whichever diagonals are chosen.
  std::vector<int> group(v.size());
  for (std::size_t t = 0; t < group.size(); ++t) group[t] = static_cast<int>(t);
  const auto root = [&](int t) {
    while (group[static_cast<std::size_t>(t)] != t)
      t = group[static_cast<std::size_t>(t)] = group[static_cast<std::size_t>(group[static_cast<std::size_t>(t)])];
    return t;
  };
  for (const auto& [t, u] : ties) group[static_cast<std::size_t>(root(t))] = root(u);
  std::vector<std::array<int, 3>> inputs;  // per group root: its input points (-1: none yet)
  std::vector<int> slot(v.size(), -1);
  for (const auto& tie : ties)
    for (const int t : tie) {
      const int r = root(t);
      if (slot[static_cast<std::size_t>(r)] < 0) {
        slot[static_cast<std::size_t>(r)] = static_cast<int>(inputs.size());
        inputs.push_back({-1, -1, -1});
      }
      auto& seen = inputs[static_cast<std::size_t>(slot[static_cast<std::size_t>(r)])];
      for (const int vertex : v[static_cast<std::size_t>(t)]) {
        if (is_super(vertex) || seen[0] == vertex || seen[1] == vertex) continue;
        if (seen[0] < 0)
          seen[0] = vertex;
        else if (seen[1] < 0)
          seen[1] = vertex;
        else
          return false;  // a third input point: some triangulation has an input triangle there
      }
    }
  return true;
}

// Visibility walk from `start`: step across any edge that has p strictly on its outer side.
// Rotating the first edge tried avoids the cycles a fixed order can fall into.
int Triangulation::locate(Vec2 p, int t) const {
  int came_from = -2;
  int rotation = 0;
  for (;;) {
    const auto& tv = v[t];
    int next = -1;
    for (int k = 0; k < 3; ++k) {
      const int i = (k + rotation) % 3;
      const int across = n[t][i];
      if (across == came_from) continue;  // p is known to be on our side of that edge
      if (orient2d(points[tv[next3(i)]], points[tv[prev3(i)]], p) < 0.0) {
        next = across;
        break;
      }
    }
    if (next < 0) return t;  // p lies in the closed triangle (never outside the super-triangle)
    came_from = t;
    t = next;
    rotation = rotation == 2 ? 0 : rotation + 1;
  }
}

void Triangulation::replace_neighbour(int t, int old_neighbour, int new_neighbour) {
  if (t < 0) return;
  auto& tn = n[t];
  tn[index_of(tn, old_neighbour)] = new_neighbour;
}

// Inserts `vertex` into triangle t (which contains it in its closure): 1->3 split inside,
// 2->4 split on an edge; then Lawson flips restore the Delaunay property around it.
void Triangulation::insert(int vertex, int t) {
  const Vec2 p = points[vertex];
  const auto tv = v[t];
  int on_edge = -1;
  for (int i = 0; i < 3; ++i) {
    if (points[tv[i]] == p) {
      const int first = input_index[vertex], second = input_index[tv[i]];
      throw InputError(fmt::format("duplicate point: points {} and {} are both at ({}, {})", std::min(first, second),
                                   std::max(first, second), p.x, p.y));
    }
    if (orient2d(points[tv[next3(i)]], points[tv[prev3(i)]], p) == 0.0) on_edge = i;
  }
  auto& stack = flip_stack_;
  if (on_edge < 0) {
    //        a                t0 = (p, b, c) in slot t, t1 = (p, c, a), t2 = (p, a, b)
    //       /|\               the old neighbours na, nb, nc lie opposite a, b, c.
    //      / p \              .
    //     b-----c
    const int a = tv[0], b = tv[1], c = tv[2];
    const int na = n[t][0], nb = n[t][1], nc = n[t][2];
    const int t0 = t, t1 = static_cast<int>(v.size()), t2 = t1 + 1;
    v[t0] = {vertex, b, c};
    n[t0] = {na, t1, t2};
    v.push_back({vertex, c, a});
    n.push_back({nb, t2, t0});
    v.push_back({vertex, a, b});
    n.push_back({nc, t0, t1});
    replace_neighbour(nb, t, t1);
    replace_neighbour(nc, t, t2);
    stack.assign({{t0, 0}, {t1, 0}, {t2, 0}});
  } else {
    //        a              p on edge b-c, shared by t = (a, b, c) and u = (d, c, b).
    //       / \             t0 = (a, b, p) in slot t, t1 = (a, p, c),
    //      b-p-c            u0 = (d, c, p) in slot u, u1 = (d, p, b).
    //       \ /
    //        d
    const int i = on_edge;
    const int a = tv[i], b = tv[next3(i)], c = tv[prev3(i)];
    const int n_ca = n[t][next3(i)], n_ab = n[t][prev3(i)];
    const int u = n[t][i];
    const int j = index_of(n[u], t);
    const int d = v[u][j];
    const int n_bd = n[u][next3(j)], n_dc = n[u][prev3(j)];
    const int t0 = t, t1 = static_cast<int>(v.size()), u0 = u, u1 = t1 + 1;
    v[t0] = {a, b, vertex};
    n[t0] = {u1, t1, n_ab};
    v.push_back({a, vertex, c});
    n.push_back({u0, n_ca, t0});
    v[u0] = {d, c, vertex};
    n[u0] = {t1, u1, n_dc};
    v.push_back({d, vertex, b});
    n.push_back({t0, n_bd, u0});
    replace_neighbour(n_ca, t, t1);
    replace_neighbour(n_bd, u, u1);
    stack.assign({{t0, 2}, {t1, 1}, {u0, 2}, {u1, 1}});
  }
  legalize(stack);
}

// Each entry (t, i) names the edge opposite the new vertex p = v[t][i]; flipping keeps p at a
// known index, so the entries stay valid without lookups.
void Triangulation::legalize(std::vector<std::array<int, 2>>& stack) {
  while (!stack.empty()) {
    const auto [t, i] = stack.back();
    stack.pop_back();
    const int u = n[t][i];
    if (u < 0) continue;
    const auto& tv = v[t];
    const int q = v[u][index_of(n[u], t)];
    if (incircle(points[tv[i]], points[tv[next3(i)]], points[tv[prev3(i)]], points[q]) > 0.0) {
      flip(t, i);
      stack.push_back({t, 0});
      stack.push_back({u, 2});
    }
  }
}

//            p                    p
//           / \                  /|\          t = (p, a, b) with p = v[t][i],
//      t_pa/ t \t_bp        t_pa/ | \t_bp     u = (q, b, a) its neighbour across a-b.
//         a-----b    ->        a t|u b        After the flip: t = (p, a, q), u = (q, b, p).
//      u_aq\ u /u_qb        u_aq\ | /u_qb
//           \ /                  \|/
//            q                    q
void Triangulation::flip(int t, int i) {
  const int u = n[t][i];
  const int j = index_of(n[u], t);
  const int p = v[t][i], a = v[t][next3(i)], b = v[t][prev3(i)];
  const int q = v[u][j];
  const int t_pa = n[t][prev3(i)], t_bp = n[t][next3(i)];
  const int u_qb = n[u][prev3(j)], u_aq = n[u][next3(j)];
  v[t] = {p, a, q};
  n[t] = {u_aq, u, t_pa};
  v[u] = {q, b, p};
  n[u] = {t_bp, t, u_qb};
  replace_neighbour(u_aq, u, t);
  replace_neighbour(t_bp, t, u);
  if (!vertex_triangle.empty()) {
    vertex_triangle[a] = t;
    vertex_triangle[b] = u;
    vertex_triangle[p] = t;
    vertex_triangle[q] = u;
  }
}

std::array<int, 2> Triangulation::find_edge(int a, int b) const {
  const int start = vertex_triangle[a];
  int t = start;
  // Counter-clockwise around a; if the fan is open (a super vertex), sweep clockwise as well.
  for (int dir = 0; dir < 2; ++dir) {
    t = start;
    do {
      const int k = index_of(v[t], a);
      if (v[t][next3(k)] == b) return {t, prev3(k)};
      t = dir == 0 ? n[t][next3(k)] : n[t][prev3(k)];
    } while (t >= 0 && t != start);
    if (t == start) break;
  }
  return {-1, -1};
}

std::vector<int> Triangulation::triangles_around(int a) const {
  std::vector<int> fan;
  const int start = vertex_triangle[a];
  int t = start;
  do {
    fan.push_back(t);
    t = n[t][next3(index_of(v[t], a))];
  } while (t >= 0 && t != start);
  if (t < 0) {  // open fan: collect the clockwise side too
    t = n[start][prev3(index_of(v[start], a))];
    while (t >= 0) {
      fan.push_back(t);
      t = n[t][prev3(index_of(v[t], a))];
    }
  }
  return fan;
}

void Triangulation::constrain(int a, int b) {
  if (on_constraint_.empty()) on_constraint_.assign(points.size(), 0);
  on_constraint_[static_cast<std::size_t>(a)] = 1;
  on_constraint_[static_cast<std::size_t>(b)] = 1;
  constrained_.insert(edge_key(a, b));
}

int Triangulation::make_delaunay() {
  int flips = 0;
  std::vector<std::array<int, 2>> stack;  // edges as (a, b) vertex pairs: triangles change under us
  for (int t = 0; t < static_cast<int>(v.size()); ++t)
    for (int i = 0; i < 3; ++i)
      if (n[t][i] > t) stack.push_back({v[t][next3(i)], v[t][prev3(i)]});
  InterruptPoll poll(16384);
  while (!stack.empty()) {
    poll.tick();
    const auto [a, b] = stack.back();
    stack.pop_back();
    if (is_constrained(a, b)) continue;
    const auto [t, i] = find_edge(a, b);
    if (t < 0) continue;  // flipped away meanwhile; its replacement was pushed then
    const int u = n[t][i];
    if (u < 0) continue;
    const int p = v[t][i];
    const int q = v[u][index_of(n[u], t)];
    if (incircle(points[p], points[a], points[b], points[q]) > 0.0) {
      flip(t, i);
      ++flips;
      stack.push_back({p, a});
      stack.push_back({a, q});
      stack.push_back({q, b});
      stack.push_back({b, p});
    }
  }
  return flips;
}

std::vector<std::array<int, 3>> Triangulation::inner_triangles() const {
  std::vector<std::array<int, 3>> out;
  out.reserve(v.size());
  for (const auto& tv : v)
    if (!is_super(tv[0]) && !is_super(tv[1]) && !is_super(tv[2]))
      out.push_back({input_index[tv[0]], input_index[tv[1]], input_index[tv[2]]});
  return out;
}

std::vector<std::array<int, 3>> delaunay_triangles(const std::vector<Vec2>& points) {
  return Triangulation(points).inner_triangles();
}

}  // namespace pdmesh
