// Trial-and-measure topology operations on one bad triangle (see topology_ops.hpp).
#include "cleanup/topology_ops.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "cleanup/measures.hpp"
#include "core/predicates.hpp"
#include "geometry/curve_projection.hpp"

namespace pdmesh::cleanup {
namespace {

constexpr double kNone = -std::numeric_limits<double>::infinity();
// A walk towards an insertion point longer than this is abandoned (the point is far away).
constexpr int kMaxWalk = 64;

}  // namespace

TopologyOps::TopologyOps(EditableMesh& mesh, Smoother& smoother, const Geometry& geometry,
                         std::function<double(Vec2)> h, TopologyOptions options)
    : mesh_(mesh), smoother_(smoother), geometry_(geometry), h_(std::move(h)), options_(options) {}

// Visibility walk from triangle `start` towards `at`; -1 when the walk would leave the domain
// (the point is outside it, or hidden behind a boundary edge), when it is on an edge, or too far.
int TopologyOps::locate(int start, Vec2 at) const {
  const auto& m = mesh_;
  int t = start;
  for (int step = 0; step < kMaxWalk; ++step) {
    int across = -2;
    for (int i = 0; i < 3 && across == -2; ++i) {
      const double side = orient2d(m.p[m.v[t][next3(i)]], m.p[m.v[t][prev3(i)]], at);
      if (side < 0.0)
        across = m.n[t][i];
      else if (side == 0.0)
        across = -1;  // on an edge: not a strictly interior point
    }
    if (across == -2) return t;
    if (across < 0) return -1;
    t = across;
  }
  return -1;
}

bool TopologyOps::edges_fit(int a, bool inserted, double shortest) {
  const auto& m = mesh_;
  // Where the boundary is segmented more finely than the field asks (fillets, small holes), the
  // triangle's own shortest edge is the size to respect: nodes at that spacing are what its fan of
  // thin boundary triangles lacks.
  const double h = inserted ? std::min(h_(m.p[a]), shortest) : h_(m.p[a]);
  m.ring(a, ring2_);
  for (int x : ring2_) {
    const double l = dist(m.p[a], m.p[x]);
    if (inserted ? l < options_.min_edge * h : l > options_.max_edge * h && !boundary_edge(a, x)) return false;
  }
  return true;
}

// A merged node's boundary edges are the curve chain's, which no collapse makes or lengthens (only
// interior nodes are removed): a coarse segment beside it (the plate's 0.31 octagon sides, where h
// is 0.18) says nothing about the edit, and counting it refused every collapse into such a corner.
bool TopologyOps::boundary_edge(int a, int x) const {
  const auto& m = mesh_;
  for (const auto [t, i] : {m.find_edge(a, x), m.find_edge(x, a)})
    if (t >= 0 && m.n[t][i] < 0) return true;
  return false;
}

bool TopologyOps::fits() {
  for (const auto& f : fit_)
    if (!mesh_.removed(f.node) && !edges_fit(f.node, f.inserted, f.shortest)) return false;
  return true;
}

void TopologyOps::relax_around(int a) {
  for (int round = 0; round < options_.relax_rounds; ++round) {
    smoother_.relax(a);
    mesh_.ring(a, ring_);
    for (int x : ring_) smoother_.relax(x);
  }
}

// After an edit around node a: Lawson flips of its link, the relaxation, and what edges_fit checks.
void TopologyOps::settle(int a, bool inserted) {
  edges_.clear();
  mesh_.push_link_edges(a, edges_);
  mesh_.legalize(edges_);
  relax_around(a);
  fit_.push_back({a, inserted, shortest_});
}

bool TopologyOps::insert_at(int t, Vec2 at) {
  const int u = locate(t, at);
  if (u < 0) return false;
  settle(mesh_.insert_in_triangle(u, at), true);
  return true;
}

bool TopologyOps::collapse_edge(int a, int b) {
  auto& m = mesh_;
  const bool both_free = m.kind[b] == NodeKind::Interior;
  const Vec2 to = both_free ? 0.5 * (m.p[a] + m.p[b]) : m.p[b];
  if (!m.collapse(a, b, to, m.arc[b])) return false;
  if (!m.star_valid(b)) return false;
  settle(b, false);
  return true;
}

bool TopologyOps::split(int t, int i) {
  auto& m = mesh_;
  const Vec2 at = 0.5 * (m.p[m.v[t][next3(i)]] + m.p[m.v[t][prev3(i)]]);
  if (!m.split_edge_valid(t, i, at)) return false;
  settle(m.split_edge(t, i, at), true);
  return true;
}

bool TopologyOps::split_boundary(int t, int i) {
  auto& m = mesh_;
  int c = -1;
  double arc_a = 0.0, arc_b = 0.0;
  if (!m.boundary_edge_arcs(t, i, c, arc_a, arc_b)) return false;
  if (geometry_.curves[c].fixed_points) return false;  // a layer front: the layer cells share its edges
  const double mid = 0.5 * (arc_a + arc_b);
  if (!(mid > std::min(arc_a, arc_b) && mid < std::max(arc_a, arc_b))) return false;
  const Vec2 at = closest_on_curve_range(geometry_.curves[c], {}, mid, mid).p;
  const Vec2 x = m.p[m.v[t][i]], a = m.p[m.v[t][next3(i)]], b = m.p[m.v[t][prev3(i)]];
  if (!(orient2d(x, a, at) > 0.0 && orient2d(x, at, b) > 0.0)) return false;
  settle(m.split_boundary_edge(t, i, at, mid, c), true);
  return true;
}

double TopologyOps::score() const {
  const double before = mesh_.touched_min_before(), after = mesh_.touched_min_after();
  const int below_before = mesh_.touched_below_before(options_.target);
  const int below_after = mesh_.touched_below_after(options_.target);
  // Kept when the worst angle rises by the gain without more triangles below the target, or when
  // fewer triangles are below the target without the worst angle dropping (a plateau move: the
  // boundary-only triangles of a gap need several insertions before the worst one can rise).
  const bool rises = after >= before + options_.gain && below_after <= below_before;
  const bool fewer_bad = after >= before && below_after < below_before;
  if (!rises && !fewer_bad) return kNone;
  // The mesh's average aspect ratio A may not rise: sum over the region of (AR - A) must not grow.
  int n_before = 0, n_after = 0;
  const double s_before = mesh_.touched_aspect_before(n_before), s_after = mesh_.touched_aspect_after(n_after);
  const double average = aspect_sum_ / aspect_count_;
  if (s_after - average * n_after > s_before - average * n_before) return kNone;
  return after;
}

void TopologyOps::candidates(int t, std::vector<Trial>& trials) {
  auto& m = mesh_;
  const auto tv = m.v[t];
  const Vec2 a = m.p[tv[0]], b = m.p[tv[1]], c = m.p[tv[2]];
  const double shortest = std::min({dist(a, b), dist(b, c), dist(c, a)});
  auto add = [&](RepairKind kind, std::function<bool()> apply) {
    trials.push_back({kind, std::move(apply), shortest});
  };
  const Vec2 cc = circumcentre(a, b, c);
  add(RepairKind::Insert, [this, t, cc] { return insert_at(t, cc); });
  const Vec2 centroid = (1.0 / 3.0) * (a + b + c);
  add(RepairKind::Insert, [this, t, centroid] { return insert_at(t, centroid); });
  for (int i = 0; i < 3; ++i) {
    const int x = tv[next3(i)], y = tv[prev3(i)];
    const bool x_free = m.kind[x] == NodeKind::Interior, y_free = m.kind[y] == NodeKind::Interior;
    if (x_free)
      add(RepairKind::Collapse, [this, x, y] { return collapse_edge(x, y); });
    else if (y_free)
      add(RepairKind::Collapse, [this, x, y] { return collapse_edge(y, x); });
    if (m.n[t][i] >= 0)
      add(RepairKind::Split, [this, t, i] { return split(t, i); });
    else if (options_.split_boundary)
      add(RepairKind::Split, [this, t, i] { return split_boundary(t, i); });
  }
  // A crowded interior vertex of the triangle: split each of its other edges, which gives a
  // neighbour the node it is missing (JIGSAW splits edges of valence-8 nodes). Valence 7 counts as
  // crowded only for a triangle below the target (these trials are most of the work).
  const std::size_t crowded = m.quality(t) < options_.target ? 7 : 8;
  for (int k = 0; k < 3; ++k) {
    const int x = tv[k];
    if (m.kind[x] != NodeKind::Interior) continue;
    m.ring(x, ring2_);
    if (ring2_.size() < crowded) continue;
    for (int y : ring2_) {
      if (y == tv[next3(k)] || y == tv[prev3(k)]) continue;
      add(RepairKind::Split, [this, x, y] {
        const auto [u, i] = mesh_.find_edge(x, y);
        return u >= 0 && split(u, i);
      });
    }
  }
}

void TopologyOps::commit_chosen() {
  auto& m = mesh_;
  int n_before = 0, n_after = 0;
  const double s_before = m.touched_aspect_before(n_before), s_after = m.touched_aspect_after(n_after);
  aspect_sum_ += s_after - s_before;
  aspect_count_ += n_after - n_before;
  m.commit();
}

RepairKind TopologyOps::repair(int t, bool compound) {
  auto& m = mesh_;
  if (!m.alive(t)) return RepairKind::None;
  std::vector<Trial> trials;
  candidates(t, trials);
  double best = kNone;
  int chosen = -1;
  for (int k = 0; k < static_cast<int>(trials.size()); ++k) {
    m.begin();
    ++trials_;
    fit_.clear();
    shortest_ = trials[k].shortest;
    double s = trials[k].apply() ? score() : kNone;
    // The size guard queries the spacing field, so only for a trial that would be chosen.
    if (s > best && !fits()) s = kNone;
    m.rollback();
    if (s > best) {
      best = s;
      chosen = k;
    }
    if (best >= options_.enough) break;  // the region is out of the work range: good enough
  }
  if (chosen < 0) return options_.compound && compound ? repair_compound(trials) : RepairKind::None;
  m.begin();
  shortest_ = trials[chosen].shortest;
  trials[chosen].apply();
  commit_chosen();
  return trials[chosen].kind;
}

bool TopologyOps::apply_pair(const std::vector<Trial>& first, int k, int j, std::vector<Trial>& second) {
  fit_.clear();
  shortest_ = first[k].shortest;
  if (!first[k].apply()) return false;
  const int w = mesh_.touched_worst_after();
  if (w < 0) return false;
  second.clear();
  candidates(w, second);
  if (j >= static_cast<int>(second.size())) return false;
  shortest_ = second[j].shortest;
  return second[j].apply();
}

// Pairs of edits for a triangle no single edit repairs: each trial on it, then each trial on the
// worst triangle that one leaves in its region, measured together against the state before both
// (the same rules as a single trial). This is how a valence-5/7 pair next to a boundary is moved
// (a split that makes a node, then a collapse that takes one away elsewhere) and how a coarse
// boundary segment gets a node and the row behind it one (split, then insert or split again).
RepairKind TopologyOps::repair_compound(const std::vector<Trial>& first) {
  auto& m = mesh_;
  double best = kNone;
  int best_k = -1, best_j = -1;
  std::vector<Trial> second;
  for (int k = 0; k < static_cast<int>(first.size()) && best < options_.enough; ++k) {
    // How many second trials follow first[k] (the list is rebuilt with each pair, the same each time).
    m.begin();
    ++trials_;
    fit_.clear();
    shortest_ = first[k].shortest;
    std::size_t count = 0;
    if (first[k].apply()) {
      const int w = m.touched_worst_after();
      if (w >= 0) {
        second.clear();
        candidates(w, second);
        count = second.size();
      }
    }
    m.rollback();
    for (int j = 0; j < static_cast<int>(count); ++j) {
      m.begin();
      ++trials_;
      ++compound_trials_;
      double s = apply_pair(first, k, j, second) ? score() : kNone;
      if (s > best && !fits()) s = kNone;
      m.rollback();
      if (s > best) {
        best = s;
        best_k = k;
        best_j = j;
      }
      if (best >= options_.enough) break;
    }
  }
  if (best_k < 0) return RepairKind::None;
  m.begin();
  apply_pair(first, best_k, best_j, second);
  commit_chosen();
  ++compound_applied_;
  for (RepairKind kind : {first[best_k].kind, second[best_j].kind}) {
    if (kind == RepairKind::Collapse)
      ++compound_removed_;
    else
      ++compound_inserted_;
  }
  return RepairKind::Compound;
}

}  // namespace pdmesh::cleanup
