// The editable mesh of the final cleanup: adjacency from a Mesh, local edits, and the journal
// that lets a trial edit be measured and rolled back.
#include "cleanup/editable_mesh.hpp"

#include <fmt/format.h>

#include <cmath>
#include <limits>
#include <unordered_map>

#include "cleanup/measures.hpp"
#include "core/errors.hpp"
#include "core/predicates.hpp"

namespace pdmesh::cleanup {
namespace {

std::uint64_t directed_key(int a, int b) {
  return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 32) | static_cast<std::uint32_t>(b);
}

constexpr double kInf = std::numeric_limits<double>::infinity();

}  // namespace

EditableMesh::EditableMesh(const Mesh& mesh, const std::vector<std::vector<int>>& curve_nodes,
                           const std::vector<std::vector<double>>& arcs)
    : curve_nodes_(curve_nodes), chain_arcs_(arcs) {
  const std::size_t np = mesh.points.size();
  p = mesh.points;
  kind = mesh.kind.size() == np ? mesh.kind : std::vector<NodeKind>(np, NodeKind::Interior);
  curve.assign(np, -1);
  arc.assign(np, 0.0);
  prev.assign(np, -1);
  next.assign(np, -1);
  vt.assign(np, -1);
  gone_.assign(np, 0);
  vert_stamp_.assign(np, 0);
  dirty_.assign(np, 1);
  chain_index_.assign(np, -1);
  // Nodes on a curve that the kinds do not mark (a mesh read without kinds) must not move either.
  for (std::size_t c = 0; c < curve_nodes.size(); ++c) {
    const auto& list = curve_nodes[c];
    for (std::size_t k = 0; k < list.size(); ++k) {
      const int a = list[k];
      const bool inner = k > 0 && k + 1 < list.size();
      if (!inner || kind[a] != NodeKind::Boundary) {
        kind[a] = NodeKind::Fixed;  // curve end points and critical corners never move
        continue;
      }
      curve[a] = static_cast<int>(c);
      chain_index_[a] = static_cast<int>(k);
      arc[a] = arcs[c][k];
      prev[a] = list[k - 1];
      next[a] = list[k + 1];
    }
  }
  v = mesh.triangles;
  n.assign(v.size(), {-1, -1, -1});
  std::unordered_map<std::uint64_t, std::pair<int, int>> half_edges;
  half_edges.reserve(3 * v.size());
  for (int t = 0; t < static_cast<int>(v.size()); ++t)
    for (int i = 0; i < 3; ++i) half_edges.emplace(directed_key(v[t][next3(i)], v[t][prev3(i)]), std::make_pair(t, i));
  for (int t = 0; t < static_cast<int>(v.size()); ++t) {
    for (int i = 0; i < 3; ++i) {
      const auto it = half_edges.find(directed_key(v[t][prev3(i)], v[t][next3(i)]));
      if (it != half_edges.end()) n[t][i] = it->second.first;
    }
    for (int a : v[t]) vt[a] = t;
  }
  // A vertex inside the domain must have a closed star; the kinds decide what may move, so an
  // interior vertex on the mesh boundary (a mesh that does not conform) is pinned.
  for (int t = 0; t < static_cast<int>(v.size()); ++t)
    for (int i = 0; i < 3; ++i)
      if (n[t][i] < 0)
        for (int a : {v[t][next3(i)], v[t][prev3(i)]})
          if (kind[a] == NodeKind::Interior) kind[a] = NodeKind::Fixed;
  tri_stamp_.assign(v.size(), 0);
}

double EditableMesh::quality(int t) const { return min_angle_sine(p[v[t][0]], p[v[t][1]], p[v[t][2]]); }
double EditableMesh::aspect(int t) const { return aspect_ratio(p[v[t][0]], p[v[t][1]], p[v[t][2]]); }

double EditableMesh::neighbour_arc(int a, int side) const {
  const int b = side == 0 ? prev[a] : next[a];
  if (kind[b] == NodeKind::Boundary) return arc[b];
  return chain_arcs_[curve[a]][chain_index_[a] + (side == 0 ? -1 : 1)];
}

void EditableMesh::star(int a, std::vector<int>& out) const {
  out.clear();
  const int start = vt[a];
  if (start < 0) return;
  // Clockwise to the first triangle of an open fan (or all the way round).
  int t = start;
  for (;;) {
    const int cw = n[t][prev3(index_of(v[t], a))];
    if (cw < 0 || cw == start) break;
    t = cw;
  }
  const int first = t;
  do {
    out.push_back(t);
    t = n[t][next3(index_of(v[t], a))];
  } while (t >= 0 && t != first);
}

void EditableMesh::ring(int a, std::vector<int>& out) const {
  std::vector<int>& fan = scratch_;
  star(a, fan);
  out.clear();
  for (int t : fan) out.push_back(v[t][next3(index_of(v[t], a))]);
  if (!fan.empty()) {
    const int last = fan.back();
    if (n[last][next3(index_of(v[last], a))] < 0) out.push_back(v[last][prev3(index_of(v[last], a))]);
  }
}

std::array<int, 2> EditableMesh::find_edge(int a, int b) const {
  // Counter-clockwise around a from vt[a]; for an open fan also clockwise (no allocation: Lawson
  // flips call this for every edge they look at).
  const int start = vt[a];
  if (start < 0) return {-1, -1};
  int t = start;
  do {
    const int k = index_of(v[t], a);
    if (v[t][next3(k)] == b) return {t, prev3(k)};
    t = n[t][next3(k)];
  } while (t >= 0 && t != start);
  if (t < 0) {
    for (t = n[start][prev3(index_of(v[start], a))]; t >= 0; t = n[t][prev3(index_of(v[t], a))]) {
      const int k = index_of(v[t], a);
      if (v[t][next3(k)] == b) return {t, prev3(k)};
    }
  }
  return {-1, -1};
}

bool EditableMesh::star_valid(int a) const {
  std::vector<int>& fan = scratch_;
  star(a, fan);
  for (int t : fan)
    if (!(orient2d(p[v[t][0]], p[v[t][1]], p[v[t][2]]) > 0.0)) return false;
  return !fan.empty();
}

// ---- journal ----------------------------------------------------------------------------------

void EditableMesh::mark_dirty(int t) {
  if (t < 0 || !alive(t)) return;
  for (int a : v[t]) dirty_[a] = 1;
}

std::vector<std::uint8_t> EditableMesh::take_dirty() {
  std::vector<std::uint8_t> out(dirty_.size(), 0);
  out.swap(dirty_);
  return out;
}

void EditableMesh::touch_triangle(int t) {
  if (!open_) mark_dirty(t);
  if (!open_ || t < 0 || t >= tri_size0_ || tri_stamp_[t] == stamp_) return;
  tri_stamp_[t] = stamp_;
  tri_log_.push_back({t, v[t], n[t], alive(t) ? quality(t) : kInf, alive(t) ? aspect(t) : 0.0});
}

void EditableMesh::touch_vertex(int a) {
  if (!open_ || a >= vert_size0_ || vert_stamp_[a] == stamp_) return;
  vert_stamp_[a] = stamp_;
  vert_log_.push_back({a, p[a], arc[a], vt[a], gone_[a]});
}

void EditableMesh::touch_star(int a) {
  if (!open_) return;
  star(a, star_scratch_);
  for (int t : star_scratch_) touch_triangle(t);
}

void EditableMesh::begin() {
  open_ = true;
  ++stamp_;
  tri_log_.clear();
  vert_log_.clear();
  tri_size0_ = triangle_slots();
  vert_size0_ = vertex_slots();
}

void EditableMesh::commit() {
  for (const SavedTriangle& s : tri_log_) {
    mark_dirty(s.t);
    if (s.v[0] >= 0)
      for (int a : s.v) dirty_[a] = 1;
  }
  for (int t = tri_size0_; t < triangle_slots(); ++t) mark_dirty(t);
  open_ = false;
  tri_log_.clear();
  vert_log_.clear();
}

void EditableMesh::rollback() {
  for (const SavedTriangle& s : tri_log_) {
    v[s.t] = s.v;
    n[s.t] = s.n;
  }
  for (const SavedVertex& s : vert_log_) {
    p[s.a] = s.p;
    arc[s.a] = s.arc;
    vt[s.a] = s.vt;
    gone_[s.a] = s.gone;
  }
  v.resize(tri_size0_);
  n.resize(tri_size0_);
  tri_stamp_.resize(tri_size0_);
  for (auto* field : {&curve, &prev, &next, &vt, &chain_index_}) field->resize(vert_size0_);
  p.resize(vert_size0_);
  kind.resize(vert_size0_);
  arc.resize(vert_size0_);
  gone_.resize(vert_size0_);
  vert_stamp_.resize(vert_size0_);
  dirty_.resize(vert_size0_);
  tri_log_.clear();
  vert_log_.clear();
  open_ = false;
}

double EditableMesh::touched_min_before() const {
  double m = kInf;
  for (const SavedTriangle& s : tri_log_) m = std::min(m, s.quality);
  return m;
}

double EditableMesh::touched_min_after() const {
  double m = kInf;
  for (const SavedTriangle& s : tri_log_)
    if (alive(s.t)) m = std::min(m, quality(s.t));
  for (int t = tri_size0_; t < triangle_slots(); ++t)
    if (alive(t)) m = std::min(m, quality(t));
  return m;
}

double EditableMesh::touched_aspect_before(int& count) const {
  double sum = 0.0;
  count = 0;
  for (const SavedTriangle& s : tri_log_) {
    if (s.quality == kInf) continue;  // a dead slot
    sum += s.aspect;
    ++count;
  }
  return sum;
}

double EditableMesh::touched_aspect_after(int& count) const {
  double sum = 0.0;
  count = 0;
  for (const SavedTriangle& s : tri_log_)
    if (alive(s.t)) {
      sum += aspect(s.t);
      ++count;
    }
  for (int t = tri_size0_; t < triangle_slots(); ++t)
    if (alive(t)) {
      sum += aspect(t);
      ++count;
    }
  return sum;
}

int EditableMesh::touched_below_before(double limit) const {
  int count = 0;
  for (const SavedTriangle& s : tri_log_) count += s.quality < limit;
  return count;
}

int EditableMesh::touched_below_after(double limit) const {
  int count = 0;
  for (const SavedTriangle& s : tri_log_) count += alive(s.t) && quality(s.t) < limit;
  for (int t = tri_size0_; t < triangle_slots(); ++t) count += alive(t) && quality(t) < limit;
  return count;
}

// ---- edits --------------------------------------------------------------------------------------

void EditableMesh::set_vt(int a, int t) {
  if (vt[a] == t) return;
  touch_vertex(a);
  vt[a] = t;
}

void EditableMesh::set_neighbour(int t, int old_neighbour, int new_neighbour) {
  if (t < 0) return;
  touch_triangle(t);
  auto& tn = n[t];
  tn[index_of(tn, old_neighbour)] = new_neighbour;
}

int EditableMesh::new_triangle(std::array<int, 3> tv, std::array<int, 3> tn) {
  v.push_back(tv);
  n.push_back(tn);
  tri_stamp_.push_back(0);
  return triangle_slots() - 1;
}

int EditableMesh::new_vertex(Vec2 at) {
  p.push_back(at);
  kind.push_back(NodeKind::Interior);
  curve.push_back(-1);
  arc.push_back(0.0);
  prev.push_back(-1);
  next.push_back(-1);
  vt.push_back(-1);
  gone_.push_back(0);
  vert_stamp_.push_back(0);
  dirty_.push_back(1);
  chain_index_.push_back(-1);
  return vertex_slots() - 1;
}

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

void EditableMesh::legalize(std::vector<std::array<int, 2>>& edges) {
  while (!edges.empty()) {
    const auto [a, b] = edges.back();
    edges.pop_back();
    if (gone_[a] || gone_[b]) continue;
    const auto [t, i] = find_edge(a, b);
    if (t < 0) continue;  // flipped away meanwhile; its replacement was pushed then
    const int u = n[t][i];
    if (u < 0) continue;  // boundary edges are constrained
    const int pv = v[t][i];
    const int q = v[u][index_of(n[u], t)];
    if (incircle(p[pv], p[a], p[b], p[q]) > 0.0) {
      flip(t, i);
      edges.push_back({pv, a});
      edges.push_back({a, q});
      edges.push_back({q, b});
      edges.push_back({b, pv});
    }
  }
}

void EditableMesh::push_link_edges(int a, std::vector<std::array<int, 2>>& edges) const {
  std::vector<int>& fan = scratch_;
  star(a, fan);
  for (int t : fan) {
    const int k = index_of(v[t], a);
    edges.push_back({v[t][next3(k)], v[t][prev3(k)]});
  }
}

void EditableMesh::move(int a, Vec2 to, double new_arc) {
  if (!open_) {
    star(a, star_scratch_);
    for (int t : star_scratch_) mark_dirty(t);
  }
  touch_star(a);
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

bool EditableMesh::collapse(int a, int b, Vec2 to, double b_arc) {
  const auto [t1, i1] = find_edge(a, b);  // t1 = (c, a, b)
  const auto [t2, i2] = find_edge(b, a);  // t2 = (d, b, a)
  if (t1 < 0 || t2 < 0) return false;
  const int c = v[t1][i1], d = v[t2][i2];
  // Link condition: a and b may share only c and d, or the collapse would pinch the mesh (and a
  // valence-3 neighbour would degenerate).
  std::vector<int> ring_a, ring_b;
  ring(a, ring_a);
  ring(b, ring_b);
  int common = 0;
  for (int x : ring_a)
    for (int y : ring_b) common += (x == y);
  if (common != 2) return false;

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

Mesh EditableMesh::to_mesh(const Mesh& original, std::vector<std::vector<int>>& curve_nodes,
                           std::vector<int>& old_of_new) const {
  std::vector<int> new_of_old(p.size(), -1);
  old_of_new.clear();
  Mesh out;
  for (int a = 0; a < vertex_slots(); ++a) {
    if (gone_[a]) continue;
    new_of_old[a] = static_cast<int>(old_of_new.size());
    old_of_new.push_back(a);
    out.points.push_back(p[a]);
    out.kind.push_back(kind[a]);
  }
  // Kinds: the constructor pins interior vertices it cannot move; report the original kinds.
  for (std::size_t k = 0; k < old_of_new.size(); ++k) {
    const int a = old_of_new[k];
    if (a < static_cast<int>(original.kind.size())) out.kind[k] = original.kind[a];
  }
  for (int t = 0; t < triangle_slots(); ++t)
    if (alive(t)) out.triangles.push_back({new_of_old[v[t][0]], new_of_old[v[t][1]], new_of_old[v[t][2]]});
  out.curve_names = original.curve_names;
  for (const BoundaryEdge& e : original.boundary_edges) out.boundary_edges.push_back({new_of_old[e.a], new_of_old[e.b], e.curve});
  curve_nodes = curve_nodes_;
  for (auto& list : curve_nodes)
    for (int& a : list) a = new_of_old[a];
  return out;
}

}  // namespace pdmesh::cleanup
