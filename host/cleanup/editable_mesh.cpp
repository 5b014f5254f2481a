// The editable mesh of the final cleanup: adjacency from a Mesh, local edits, and the journal
// that lets a trial edit be measured and rolled back.
#include "cleanup/editable_mesh.hpp"

#include <fmt/format.h>

#include <cmath>
#include <limits>
#include <algorithm>
#include <unordered_map>
#include <unordered_set>

#include "cleanup/measures.hpp"
#include "core/errors.hpp"
#include "core/parallel.hpp"
#include "core/predicates.hpp"

namespace pdmesh::cleanup {
namespace {

std::uint64_t directed_key(int a, int b) {
  return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 32) | static_cast<std::uint32_t>(b);
}

constexpr double kInf = std::numeric_limits<double>::infinity();

}  // namespace

EditableMesh::EditableMesh(const Mesh& mesh, const std::vector<std::vector<int>>& curve_nodes,
                           const std::vector<std::vector<double>>& arcs, std::size_t threads)
    : fixed_on_curve_(curve_nodes.size()) {
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
  marked_at_.assign(np, epoch_);
  unmoved_.assign(np, 0);
  // Nodes on a curve that the kinds do not mark (a mesh read without kinds) must not move either.
  // An embedded constraint (Mesh::constraint_curves) has triangles on both sides: the mesh is cut
  // along it (no neighbours across its edges, so no flip crosses it) and its nodes are pinned, so
  // that no operation needs a vertex with two open fans; its edges are no splittable boundary edges.
  std::unordered_set<std::uint64_t> cut;
  for (std::size_t c = 0; c < curve_nodes.size(); ++c) {
    const auto& list = curve_nodes[c];
    const bool open = c < mesh.constraint_curves.size() && mesh.constraint_curves[c] != 0;
    for (std::size_t k = 0; k < list.size(); ++k) {
      const int a = list[k];
      const bool inner = k > 0 && k + 1 < list.size();
      if (open) {
        kind[a] = NodeKind::Fixed;
        fixed_on_curve_[c].push_back({a, arcs[c][k]});
        if (k > 0) cut.insert(directed_key(std::min(list[k - 1], a), std::max(list[k - 1], a)));
        continue;
      }
      if (!inner || kind[a] != NodeKind::Boundary) {
        kind[a] = NodeKind::Fixed;  // curve end points and critical corners never move
        fixed_on_curve_[c].push_back({a, arcs[c][k]});
        // A boundary edge between two fixed nodes has no sliding node to name its curve.
        if (k > 0 && kind[list[k - 1]] == NodeKind::Fixed)
          fixed_edges_[edge_key(list[k - 1], a)] = {static_cast<int>(c), list[k - 1], arcs[c][k - 1], arcs[c][k]};
        continue;
      }
      curve[a] = static_cast<int>(c);
      arc[a] = arcs[c][k];
      prev[a] = list[k - 1];
      next[a] = list[k + 1];
    }
  }
  v = mesh.triangles;
  n.assign(v.size(), {-1, -1, -1});
  // The triangles around each vertex, ascending (compressed rows: `first[a]` .. `first[a + 1]`). The
  // neighbour across t's edge b -> a (counter-clockwise in t) is the triangle with a -> b, found among
  // a's triangles; where a broken mesh has several, the lowest (triangle, local index) is taken. Each
  // triangle writes only its own neighbours, so the search runs on several threads.
  std::vector<std::size_t> first(np + 1, 0);
  for (const auto& tv : v)
    for (int a : tv) ++first[static_cast<std::size_t>(a) + 1];
  for (std::size_t a = 0; a < np; ++a) first[a + 1] += first[a];
  std::vector<int> around(first[np]);
  {
    std::vector<std::size_t> fill(first.begin(), first.end() - 1);
    for (int t = 0; t < static_cast<int>(v.size()); ++t)
      for (int a : v[t]) around[fill[static_cast<std::size_t>(a)]++] = t;
  }
  // A vertex's incident triangle: the last one that has it.
  for (std::size_t a = 0; a < np; ++a)
    if (first[a + 1] > first[a]) vt[a] = around[first[a + 1] - 1];
  parallel_for(
      v.size(),
      [&](std::size_t slot) {
        const auto& tv = v[slot];
        for (int i = 0; i < 3; ++i) {
          const int a = tv[prev3(i)], b = tv[next3(i)];
          if (!cut.empty() && cut.count(directed_key(std::min(a, b), std::max(a, b)))) continue;
          const auto ua = static_cast<std::size_t>(a);
          for (std::size_t k = first[ua]; k < first[ua + 1] && n[slot][i] < 0; ++k) {
            const auto& sv = v[static_cast<std::size_t>(around[k])];
            for (int j = 0; j < 3; ++j)
              if (sv[next3(j)] == a && sv[prev3(j)] == b) {
                n[slot][i] = around[k];
                break;
              }
          }
        }
      },
      16384, threads);
  // A vertex inside the domain must have a closed star; the kinds decide what may move, so an
  // interior vertex on the mesh boundary (a mesh that does not conform) is pinned.
  for (int t = 0; t < static_cast<int>(v.size()); ++t)
    for (int i = 0; i < 3; ++i)
      if (n[t][i] < 0)
        for (int a : {v[t][next3(i)], v[t][prev3(i)]})
          if (kind[a] == NodeKind::Interior) kind[a] = NodeKind::Fixed;
  tri_stamp_.assign(v.size(), 0);
  tri_marked_at_.assign(v.size(), epoch_);
}

int EditableMesh::sharp_corner_in(int t) const {
  // Vertices added after set_sharp_corners() are no corners. Both edges at the corner on the
  // boundary: t is the only triangle there.
  for (int k = 0; k < 3; ++k)
    if (static_cast<std::size_t>(v[t][k]) < sharp_.size() && sharp_[v[t][k]] && n[t][next3(k)] < 0 &&
        n[t][prev3(k)] < 0)
      return k;
  return -1;
}

void EditableMesh::set_sharp_corners(double degrees) {
  sharp_.assign(p.size(), 0);
  std::vector<int> fan;
  for (int a = 0; a < vertex_slots(); ++a) {
    if (kind[a] != NodeKind::Fixed || removed(a)) continue;
    star(a, fan);
    double sum = 0.0;
    bool open = false;
    for (int t : fan) {
      const int k = index_of(v[t], a);
      const Vec2 u = p[v[t][next3(k)]] - p[a], w = p[v[t][prev3(k)]] - p[a];
      sum += std::atan2(cross(u, w), u.x * w.x + u.y * w.y);
      open = open || n[t][next3(k)] < 0;
    }
    // A closed star (an interior fixed node) has 360 degrees around it.
    if (open && sum * 57.29577951308232 < degrees) sharp_[a] = 1;
  }
}
double EditableMesh::aspect(int t) const { return aspect_ratio(p[v[t][0]], p[v[t][1]], p[v[t][2]]); }

double EditableMesh::neighbour_arc(int a, int side) const {
  const int b = side == 0 ? prev[a] : next[a];
  if (kind[b] == NodeKind::Boundary) return arc[b];
  // A fixed neighbour: its place on a's curve before (after) a. On a closed curve the same node
  // is both the first and the last entry, at arc 0 and at the curve's length.
  double best = side == 0 ? -HUGE_VAL : HUGE_VAL;
  for (const FixedEntry& e : fixed_on_curve_[curve[a]]) {
    if (e.node != b) continue;
    if (side == 0 && e.arc < arc[a]) best = std::max(best, e.arc);
    if (side == 1 && e.arc > arc[a]) best = std::min(best, e.arc);
  }
  return best;
}

bool EditableMesh::boundary_edge_arcs(int t, int i, int& c, double& arc_a, double& arc_b) const {
  const int a = v[t][next3(i)], b = v[t][prev3(i)];
  if (n[t][i] >= 0) return false;
  auto along = [&](int x, int y, double& arc_x, double& arc_y) {  // x slides on its curve
    if (y != prev[x] && y != next[x]) return false;
    c = curve[x];
    arc_x = arc[x];
    arc_y = neighbour_arc(x, y == prev[x] ? 0 : 1);
    return std::isfinite(arc_y);
  };
  if (kind[a] == NodeKind::Boundary && curve[a] >= 0) return along(a, b, arc_a, arc_b);
  if (kind[b] == NodeKind::Boundary && curve[b] >= 0) return along(b, a, arc_b, arc_a);
  const auto it = fixed_edges_.find(edge_key(a, b));
  if (it == fixed_edges_.end()) return false;
  const FixedEdge& e = it->second;
  c = e.curve;
  arc_a = a == e.first ? e.first_arc : e.second_arc;
  arc_b = a == e.first ? e.second_arc : e.first_arc;
  return true;
}

void EditableMesh::star(int a, std::vector<int>& out) const {
  out.clear();
  const int start = vt[a];
  if (start < 0) return;
  // A closed star (an interior vertex, the common case) in one walk counter-clockwise from vt[a]; it
  // is listed from the triangle after vt[a], as the walk below lists it, since the order of the star
  // is the order in which callers sum over it.
  for (int t = start;;) {
    out.push_back(t);
    t = n[t][next3(index_of(v[t], a))];
    if (t < 0) break;
    if (t == start) {
      std::rotate(out.begin(), out.begin() + 1, out.end());
      return;
    }
  }
  out.clear();
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

int EditableMesh::common_neighbours(int a, int b) const {
  std::vector<int> ring_a, ring_b;
  ring(a, ring_a);
  ring(b, ring_b);
  int common = 0;
  for (int x : ring_a)
    for (int y : ring_b) common += (x == y);
  return common;
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
  tri_marked_at_[t] = epoch_;
  for (int a : v[t]) mark_vertex(a);
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
  vert_log_.push_back({a, p[a], arc[a], vt[a], prev[a], next[a], gone_[a]});
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
      for (int a : s.v) mark_vertex(a);
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
    prev[s.a] = s.prev;
    next[s.a] = s.next;
    gone_[s.a] = s.gone;
  }
  v.resize(tri_size0_);
  n.resize(tri_size0_);
  tri_stamp_.resize(tri_size0_);
  tri_marked_at_.resize(tri_size0_);
  for (auto* field : {&curve, &prev, &next, &vt}) field->resize(vert_size0_);
  p.resize(vert_size0_);
  kind.resize(vert_size0_);
  arc.resize(vert_size0_);
  gone_.resize(vert_size0_);
  vert_stamp_.resize(vert_size0_);
  dirty_.resize(vert_size0_);
  marked_at_.resize(vert_size0_);
  unmoved_.resize(vert_size0_);
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

int EditableMesh::touched_worst_after() const {
  int worst = -1;
  double lowest = kInf;
  auto consider = [&](int t) {
    if (!alive(t)) return;
    const double q = quality(t);
    if (q < lowest || (q == lowest && t < worst)) {
      lowest = q;
      worst = t;
    }
  };
  for (const SavedTriangle& s : tri_log_) consider(s.t);
  for (int t = tri_size0_; t < triangle_slots(); ++t) consider(t);
  return worst;
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
  tri_marked_at_.push_back(epoch_);
  if (!open_) last_mark_ = epoch_;  // a commit marks the transaction's new slots
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
  marked_at_.push_back(epoch_);
  if (!open_) last_mark_ = epoch_;
  unmoved_.push_back(0);
  return vertex_slots() - 1;
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
  out.constraint_curves = original.constraint_curves;
  // The curve chains: each curve's fixed nodes at their arcs merged with its sliding nodes, ordered by
  // arc (a sliding node stays strictly between its neighbours, so this is the chain order, with the
  // nodes that boundary splits added); the boundary edges join consecutive chain nodes.
  std::vector<std::vector<std::pair<double, int>>> chains(fixed_on_curve_.size());
  for (std::size_t c = 0; c < chains.size(); ++c)
    for (const FixedEntry& e : fixed_on_curve_[c]) chains[c].push_back({e.arc, e.node});
  for (int a = 0; a < vertex_slots(); ++a)
    if (!gone_[a] && kind[a] == NodeKind::Boundary && curve[a] >= 0) chains[curve[a]].push_back({arc[a], a});
  curve_nodes.assign(chains.size(), {});
  for (std::size_t c = 0; c < chains.size(); ++c) {
    std::stable_sort(chains[c].begin(), chains[c].end(),
                     [](const auto& x, const auto& y) { return x.first < y.first; });
    for (const auto& [position, a] : chains[c]) curve_nodes[c].push_back(new_of_old[a]);
    for (std::size_t k = 0; k + 1 < curve_nodes[c].size(); ++k)
      out.boundary_edges.push_back({curve_nodes[c][k], curve_nodes[c][k + 1], static_cast<int>(c)});
  }
  return out;
}

}  // namespace pdmesh::cleanup
