// The local edits of the editable mesh (editable_mesh.hpp): flip, Lawson legalisation, vertex move,
// 1->3 insertion, interior and boundary edge splits, edge collapse. Each goes through the journal
// hooks of editable_mesh.cpp, so a trial edit can be measured and undone. Also the Delaunay test of
// the whole mesh that legalize() would make.
#include <algorithm>
#include <atomic>

#include "cleanup/editable_mesh.hpp"
#include "core/parallel.hpp"
#include "core/predicates.hpp"

namespace pdmesh::cleanup {

//            p                    p
//           / \                  /|\          t = (p, a, b) with p = v[t][i],
//      t_pa/ t \t_bp        t_pa/ | \t_bp     u = (q, b, a) its neighbour across a-b.
//         a-----b    ->        a t|u b        After the flip: t = (p, a, q), u = (q, b, p).
//      u_aq\ u /u_qb        u_aq\ | /u_qb
//           \ /                  \|/
//            q                    q
void EditableMesh::flip(int t, int i) {
  const int u = n[t][i];
  const int j = index_of(n[u], t);
  const int pv = v[t][i], a = v[t][next3(i)], b = v[t][prev3(i)];
  const int q = v[u][j];
  const int t_pa = n[t][prev3(i)], t_bp = n[t][next3(i)];
  const int u_qb = n[u][prev3(j)], u_aq = n[u][next3(j)];
  touch_triangle(t);
  touch_triangle(u);
  v[t] = {pv, a, q};
  n[t] = {u_aq, u, t_pa};
  v[u] = {q, b, pv};
  n[u] = {t_bp, t, u_qb};
  set_neighbour(u_aq, u, t);
  set_neighbour(t_bp, t, u);
  set_vt(a, t);
  set_vt(b, u);
  set_vt(pv, t);
  set_vt(q, u);
}

void EditableMesh::legalize(std::vector<EdgeRef>& edges) {
  while (!edges.empty()) {
    const auto [a, b, h] = edges.back();
    edges.pop_back();
    if (gone_[a] || gone_[b] || !alive(h)) continue;
    // The triangle t with a -> b counter-clockwise, opposite v[t][i]. When h no longer has the edge, a
    // flip changed h after the push: that flip pushed the edge again with its new triangle (it pushes
    // its quadrilateral's four sides) and that entry, above this one, has been handled; or the edge
    // was flipped away.
    const int ha = index_of(v[h], a), hb = index_of(v[h], b);
    if (v[h][ha] != a || v[h][hb] != b) continue;
    int t = h, i = 3 - ha - hb;
    if (v[h][next3(ha)] != b) {  // h has b -> a: t is its neighbour across the edge
      t = n[h][i];
      if (t < 0) continue;  // boundary edges are constrained
      i = index_of(n[t], h);
    }
    const int u = n[t][i];
    if (u < 0) continue;  // boundary edges are constrained
    const int pv = v[t][i];
    const int q = v[u][index_of(n[u], t)];
    if (incircle(p[pv], p[a], p[b], p[q]) > 0.0) {
      flip(t, i);  // t = (pv, a, q), u = (q, b, pv)
      edges.push_back({pv, a, t});
      edges.push_back({a, q, t});
      edges.push_back({q, b, u});
      edges.push_back({b, pv, u});
    }
  }
}

bool EditableMesh::locally_delaunay(std::size_t threads) const {
  std::atomic<bool> illegal{false};
  parallel_for(
      static_cast<std::size_t>(triangle_slots()),
      [&](std::size_t slot) {
        const int t = static_cast<int>(slot);
        if (!alive(t) || illegal.load(std::memory_order_relaxed)) return;
        for (int i = 0; i < 3; ++i) {
          // The edge a -> b opposite v[t][i], as legalize() tests it from t.
          const int a = v[t][next3(i)], b = v[t][prev3(i)], u = n[t][i];
          if (u < 0 || gone_[a] || gone_[b]) continue;
          const int q = v[u][index_of(n[u], t)];
          if (incircle(p[v[t][i]], p[a], p[b], p[q]) > 0.0) illegal.store(true, std::memory_order_relaxed);
        }
      },
      16384, threads);
  return !illegal.load();
}

void EditableMesh::push_link_edges(int a, std::vector<EdgeRef>& edges) const {
  std::vector<int>& fan = scratch_;
  star(a, fan);
  for (int t : fan) {
    const int k = index_of(v[t], a);
    edges.push_back({v[t][next3(k)], v[t][prev3(k)], t});
  }
}

void EditableMesh::move(int a, Vec2 to, double new_arc) {
  star(a, star_scratch_);
  move(a, to, new_arc, star_scratch_);
}

void EditableMesh::move(int a, Vec2 to, double new_arc, const std::vector<int>& a_star) {
  for (int t : a_star) touch_triangle(t);  // journals it in a transaction, else marks it dirty
  touch_vertex(a);
  p[a] = to;
  arc[a] = new_arc;
}

int EditableMesh::insert_in_triangle(int t, Vec2 at) {
  //        a                t0 = (w, b, c) in slot t, t1 = (w, c, a), t2 = (w, a, b);
  //       /|\               na, nb, nc lie opposite a, b, c.
  //      / w \              .
  //     b-----c
  const auto tv = v[t];
  const int a = tv[0], b = tv[1], c = tv[2];
  const int na = n[t][0], nb = n[t][1], nc = n[t][2];
  touch_triangle(t);
  const int w = new_vertex(at);
  const int t0 = t, t1 = triangle_slots(), t2 = t1 + 1;
  v[t0] = {w, b, c};
  n[t0] = {na, t1, t2};
  new_triangle({w, c, a}, {nb, t2, t0});
  new_triangle({w, a, b}, {nc, t0, t1});
  set_neighbour(nb, t, t1);
  set_neighbour(nc, t, t2);
  set_vt(w, t0);
  set_vt(a, t1);
  set_vt(b, t0);
  set_vt(c, t0);
  return w;
}

bool EditableMesh::split_edge_valid(int t, int i, Vec2 at) const {
  const int u = n[t][i];
  if (u < 0) return false;
  const int a = v[t][i], b = v[t][next3(i)], c = v[t][prev3(i)];
  const int d = v[u][index_of(n[u], t)];
  return orient2d(p[a], p[b], at) > 0.0 && orient2d(p[a], at, p[c]) > 0.0 && orient2d(p[d], p[c], at) > 0.0 &&
         orient2d(p[d], at, p[b]) > 0.0;
}

int EditableMesh::split_edge(int t, int i, Vec2 at) {
  //        a              w on edge b-c, shared by t = (a, b, c) and u = (d, c, b).
  //       / \             t0 = (a, b, w) in slot t, t1 = (a, w, c),
  //      b-w-c            u0 = (d, c, w) in slot u, u1 = (d, w, b).
  //       \ /
  //        d
  const int a = v[t][i], b = v[t][next3(i)], c = v[t][prev3(i)];
  const int n_ca = n[t][next3(i)], n_ab = n[t][prev3(i)];
  const int u = n[t][i];
  const int j = index_of(n[u], t);
  const int d = v[u][j];
  const int n_bd = n[u][next3(j)], n_dc = n[u][prev3(j)];
  touch_triangle(t);
  touch_triangle(u);
  const int w = new_vertex(at);
  const int t0 = t, t1 = triangle_slots(), u0 = u, u1 = t1 + 1;
  v[t0] = {a, b, w};
  n[t0] = {u1, t1, n_ab};
  new_triangle({a, w, c}, {u0, n_ca, t0});
  v[u0] = {d, c, w};
  n[u0] = {t1, u1, n_dc};
  new_triangle({d, w, b}, {t0, n_bd, u0});
  set_neighbour(n_ca, t, t1);
  set_neighbour(n_bd, u, u1);
  set_vt(w, t0);
  set_vt(a, t0);
  set_vt(b, t0);
  set_vt(c, t1);
  set_vt(d, u0);
  return w;
}

int EditableMesh::split_boundary_edge(int t, int i, Vec2 at, double at_arc, int c) {
  //        x              t = (x, a, b) with a -> b on the boundary, split at w on the curve:
  //       / \             t0 = (x, a, w) in slot t, t1 = (x, w, b).
  //      a-w-b
  const int x = v[t][i], a = v[t][next3(i)], b = v[t][prev3(i)];
  const int n_bx = n[t][next3(i)], n_xa = n[t][prev3(i)];
  double arc_a = 0.0, arc_b = 0.0;
  int curve_ab = -1;
  boundary_edge_arcs(t, i, curve_ab, arc_a, arc_b);
  touch_triangle(t);
  const int w = new_vertex(at);
  kind[w] = NodeKind::Boundary;
  curve[w] = c;
  arc[w] = at_arc;
  const int t0 = t, t1 = triangle_slots();
  v[t0] = {x, a, w};
  n[t0] = {-1, t1, n_xa};
  new_triangle({x, w, b}, {-1, n_bx, t0});
  set_neighbour(n_bx, t, t1);
  set_vt(w, t0);
  set_vt(a, t0);
  set_vt(b, t1);
  set_vt(x, t0);
  // The chain: w goes between the end nearer the curve's start and the other.
  const int lo = arc_a < arc_b ? a : b, hi = arc_a < arc_b ? b : a;
  prev[w] = lo;
  next[w] = hi;
  if (kind[lo] == NodeKind::Boundary) {
    touch_vertex(lo);
    next[lo] = w;
  }
  if (kind[hi] == NodeKind::Boundary) {
    touch_vertex(hi);
    prev[hi] = w;
  }
  return w;
}

bool EditableMesh::collapse(int a, int b, Vec2 to, double b_arc) {
  const auto [t1, i1] = find_edge(a, b);  // t1 = (c, a, b)
  const auto [t2, i2] = find_edge(b, a);  // t2 = (d, b, a)
  if (t1 < 0 || t2 < 0) return false;
  const int c = v[t1][i1], d = v[t2][i2];
  // Link condition: a and b may share only c and d, or the collapse would pinch the mesh (and a
  // valence-3 neighbour would degenerate).
  if (common_neighbours(a, b) != 2) return false;

  touch_star(a);
  touch_star(b);
  const int n_bc = n[t1][index_of(v[t1], a)], n_ca = n[t1][index_of(v[t1], b)];
  const int n_ad = n[t2][index_of(v[t2], b)], n_db = n[t2][index_of(v[t2], a)];
  star(a, star_scratch_);
  const std::vector<int> fan = star_scratch_;
  set_neighbour(n_ca, t1, n_bc);
  set_neighbour(n_bc, t1, n_ca);
  set_neighbour(n_ad, t2, n_db);
  set_neighbour(n_db, t2, n_ad);
  for (int t : fan) {
    if (t == t1 || t == t2) continue;
    touch_triangle(t);
    v[t][index_of(v[t], a)] = b;
  }
  for (int t : {t1, t2}) {
    touch_triangle(t);
    v[t] = {-1, -1, -1};
    n[t] = {-1, -1, -1};
  }
  set_vt(b, n_ca);
  set_vt(c, n_ca);
  set_vt(d, n_ad);
  touch_vertex(a);
  vt[a] = -1;
  gone_[a] = 1;
  touch_vertex(b);
  p[b] = to;
  arc[b] = b_arc;
  return true;
}

//        c              t1 = (c, a, b) or (c, b, a) on the boundary edge a-b: a goes, b stays; the
//       / \             triangles across c-a and b-c become neighbours, a's other triangles take b.
//      a---b
bool EditableMesh::collapse_boundary(int a, int b) {
  if (kind[a] != NodeKind::Boundary || curve[a] < 0 || (b != prev[a] && b != next[a])) return false;
  const int other = b == next[a] ? prev[a] : next[a];
  if (other == b || (kind[other] != NodeKind::Boundary && kind[b] != NodeKind::Boundary)) return false;
  std::array<int, 2> edge = find_edge(a, b);
  if (edge[0] < 0) edge = find_edge(b, a);
  const int t1 = edge[0], i1 = edge[1];
  if (t1 < 0 || n[t1][i1] >= 0) return false;
  const int c = v[t1][i1];
  const int n_bc = n[t1][index_of(v[t1], a)], n_ca = n[t1][index_of(v[t1], b)];
  if (n_bc < 0 || n_ca < 0) return false;
  if (common_neighbours(a, b) != 1) return false;

  touch_star(a);
  touch_star(b);
  star(a, star_scratch_);
  const std::vector<int> fan = star_scratch_;
  set_neighbour(n_ca, t1, n_bc);
  set_neighbour(n_bc, t1, n_ca);
  for (int t : fan) {
    if (t == t1) continue;
    touch_triangle(t);
    v[t][index_of(v[t], a)] = b;
  }
  touch_triangle(t1);
  v[t1] = {-1, -1, -1};
  n[t1] = {-1, -1, -1};
  set_vt(b, n_ca);
  set_vt(c, n_ca);
  touch_vertex(a);
  vt[a] = -1;
  gone_[a] = 1;
  // The chain: other - b in a's place.
  if (kind[other] == NodeKind::Boundary) {
    touch_vertex(other);
    (other == prev[a] ? next[other] : prev[other]) = b;
  }
  if (kind[b] == NodeKind::Boundary) {
    touch_vertex(b);
    (b == next[a] ? prev[b] : next[b]) = other;
  }
  return true;
}

}  // namespace pdmesh::cleanup
