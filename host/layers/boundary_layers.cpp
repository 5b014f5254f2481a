// build_boundary_layers(): rays, thickness limits, the layer cells and fronts, and the final checks
// that shrink the rays of any inverted cell or crossing edge until none is left.
#include "layers/boundary_layers.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <unordered_set>

#include "core/errors.hpp"
#include "core/input_file.hpp"
#include "core/predicates.hpp"
#include "layers/layers_detail.hpp"

namespace pdmesh {

using namespace layers_detail;

void check_layer_settings(const LayerSettings& s) {
  auto fail = [](const std::string& what) { throw InputError("boundary layer: " + what); };
  if (!(std::isfinite(s.first_height) && s.first_height > 0.0))
    fail(fmt::format("first_height = {} must be a positive number", s.first_height));
  if (!(std::isfinite(s.growth) && s.growth > 1.0)) fail(fmt::format("growth = {} must be greater than 1", s.growth));
  if (s.growth > 3.0) fail(fmt::format("growth = {} is above 3", s.growth));
  const bool by_thickness = s.thickness != 0.0;
  if (by_thickness == (s.layers != 0))
    fail(fmt::format("give either thickness or layers, not {} (thickness = {}, layers = {})",
                     by_thickness ? "both" : "neither", s.thickness, s.layers));
  if (by_thickness && !(std::isfinite(s.thickness) && s.thickness > 0.0))
    fail(fmt::format("thickness = {} must be a positive number", s.thickness));
  if (by_thickness && s.first_height > s.thickness)
    fail(fmt::format("first_height = {} is above the thickness = {}", s.first_height, s.thickness));
  if (s.layers < 0 || s.layers > 10000) fail(fmt::format("layers = {} must be in 1..10000", s.layers));
  if (by_thickness) {
    const double n = std::log1p(s.thickness * (s.growth - 1.0) / s.first_height) / std::log(s.growth);
    if (!(n <= 10000.0))
      fail(fmt::format("thickness = {} needs {:.0f} layers of first_height = {} and growth = {} (at most 10000)",
                       s.thickness, n, s.first_height, s.growth));
  }
  if (!(s.fan_angle_deg > 0.0 && s.fan_angle_deg < 180.0))
    fail(fmt::format("fan_angle = {} must be in (0, 180) degrees", s.fan_angle_deg));
  if (!(s.fan_elements_per_pi >= 1.0 && s.fan_elements_per_pi <= 100.0))
    fail(fmt::format("fan_elements_per_pi = {} must be in [1, 100]", s.fan_elements_per_pi));
  if (!(s.max_ray_tilt_deg >= 0.0 && s.max_ray_tilt_deg < 45.0))
    fail(fmt::format("max_ray_tilt = {} must be in [0, 45) degrees", s.max_ray_tilt_deg));
  if (s.smoothing_passes < 0 || s.smoothing_passes > 1000)
    fail(fmt::format("smoothing_passes = {} must be in 0..1000", s.smoothing_passes));
  if (!(s.max_jump > 1.0 && s.max_jump <= 10.0)) fail(fmt::format("max_jump = {} must be in (1, 10]", s.max_jump));
  if (!(s.max_slope > 0.0 && s.max_slope <= 100.0))
    fail(fmt::format("max_slope = {} must be in (0, 100]", s.max_slope));
  if (!(s.gap_fraction > 0.0 && s.gap_fraction <= 0.5))
    fail(fmt::format("gap_fraction = {} must be in (0, 0.5]", s.gap_fraction));
  if (!(s.cross_fraction > 0.0 && s.cross_fraction < 1.0))
    fail(fmt::format("cross_fraction = {} must be in (0, 1)", s.cross_fraction));
  if (!(s.core_room >= 0.0 && s.core_room <= 10.0)) fail(fmt::format("core_room = {} must be in [0, 10]", s.core_room));
  if (!(s.merge_span >= 0.0 && s.merge_span <= 100.0))
    fail(fmt::format("merge_span = {} must be in [0, 100]", s.merge_span));
  if (!(s.split_span == 0.0 || (s.split_span >= 1.0 && s.split_span <= 100.0)))
    fail(fmt::format("split_span = {} must be 0 or in [1, 100]", s.split_span));
}

double fan_elements_matching_core(double growth, double at_least) {
  return std::min(100.0, std::max(at_least, std::numbers::pi / (growth - 1.0)));
}

std::vector<int> curves_by_name(const Geometry& geometry, const std::vector<std::string>& names,
                                const std::string& what) {
  std::vector<int> out;
  for (const std::string& name : names) {
    int found = -1;
    for (std::size_t c = 0; c < geometry.curves.size(); ++c)
      if (geometry.curves[c].name == name) found = static_cast<int>(c);
    // A group's name (a mesh file's name on several curves) stands for all of them.
    const auto group = std::find_if(geometry.groups.begin(), geometry.groups.end(),
                                    [&](const CurveGroup& g) { return g.name == name; });
    if (group != geometry.groups.end()) {
      for (const std::string& member : group->curves)
        for (std::size_t c = 0; c < geometry.curves.size(); ++c)
          if (geometry.curves[c].name == member) out.push_back(static_cast<int>(c));
      continue;
    }
    if (found < 0) {
      std::string known;
      for (const Curve& c : geometry.curves) known += (known.empty() ? "" : ", ") + c.name;
      throw InputError(
          fmt::format("{}: unknown curve '{}' (the geometry's curves: {})", what, quote_input(name), known));
    }
    out.push_back(found);
  }
  return out;
}

namespace {

// Each ray's node heights over the wall: 0, then the stack's heights, the last at the ray's thickness.
std::vector<std::vector<double>> ray_heights(const std::vector<int>& count, const std::vector<double>& top,
                                             const LayerSettings& settings) {
  std::vector<std::vector<double>> height(count.size());
  for (std::size_t r = 0; r < count.size(); ++r) {
    height[r] = {0.0};
    for (int k = 1; k <= count[r]; ++k)
      height[r].push_back(k < count[r] ? stack_height(settings.first_height, settings.growth, k) : top[r]);
  }
  return height;
}

// Each ray's nodes: the wall node, then one node per height up to the layer its column ends at
// (end[r], -1: all). `height` is cut there; `owner` gets each node's ray.
void place_ray_nodes(LayerMesh& m, const std::vector<int>& count, const std::vector<double>& top,
                     const std::vector<int>& end, const LayerSettings& settings,
                     std::vector<std::vector<double>>& height, std::vector<int>& owner) {
  const double h1 = settings.first_height;
  for (std::size_t r = 0; r < m.rays.size(); ++r) {
    LayerRay& ray = m.rays[r];
    const Vec2 p = m.nodes[ray.wall_node];
    ray.nodes = {ray.wall_node};
    ray.merged = end[r] >= 0;
    if (ray.merged) height[r].resize(static_cast<std::size_t>(end[r]) + 1);
    const int n = count[r];
    ray.thickness = n > 0 ? top[r] : 0.0;
    for (std::size_t k = 1; k < height[r].size(); ++k) {
      ray.nodes.push_back(static_cast<int>(m.nodes.size()));
      m.nodes.push_back(p + (height[r][k] / ray.correction) * ray.direction);
      owner.push_back(static_cast<int>(r));
    }
    ray.last_growth = n >= 2 && !ray.merged ? (top[r] - stack_height(h1, settings.growth, n - 1)) /
                                                  (h1 * std::pow(settings.growth, n - 2))
                                            : (n >= 2 ? settings.growth : 1.0);
  }
}

// The smallest cosine of a triangle's angles (the larger, the smaller its largest angle).
double min_cos(const LayerMesh& m, int a, int b, int c) {
  double lo = 1.0;
  const int t[3] = {a, b, c};
  for (int i = 0; i < 3; ++i) {
    const Vec2 u = m.nodes[t[(i + 1) % 3]] - m.nodes[t[i]], w = m.nodes[t[(i + 2) % 3]] - m.nodes[t[i]];
    lo = std::min(lo, dot(u, w) / (norm(u) * norm(w)));
  }
  return lo;
}

// Adds a cell (v[3] < 0: a triangle); with split_quads a quad as two triangles, along the diagonal
// whose triangles have the smaller largest angle (cosines compared).
void add_cell(LayerMesh& m, bool split_quads, std::array<int, 4> v, LayerCellKind kind, int curve, int layer) {
  if (v[3] >= 0 && split_quads) {
    const double d02 = std::min(min_cos(m, v[0], v[1], v[2]), min_cos(m, v[0], v[2], v[3]));
    const double d13 = std::min(min_cos(m, v[0], v[1], v[3]), min_cos(m, v[1], v[2], v[3]));
    const LayerCellKind k = kind == LayerCellKind::Quad ? LayerCellKind::Split : kind;
    if (d02 >= d13) {
      m.cells.push_back({{v[0], v[1], v[2], -1}, k, curve, layer});
      m.cells.push_back({{v[0], v[2], v[3], -1}, k, curve, layer});
    } else {
      m.cells.push_back({{v[0], v[1], v[3], -1}, k, curve, layer});
      m.cells.push_back({{v[1], v[2], v[3], -1}, k, curve, layer});
    }
    return;
  }
  m.cells.push_back({v, kind, curve, layer});
}

// The cells between two neighbouring rays a and b (of heights ha, hb) from layer `from` to layer `to`
// of both (-1: their tops). Their columns are zipped upwards: a quad while both its lower and its
// upper nodes are level (heights within half the thinner layer and 0.3 x the width between them: no
// skewed quad), else a triangle advancing the column whose next node is lower. A fan (two rays
// from one wall node) starts with a triangle.
void zip_columns(LayerMesh& m, bool split_quads, int a, int b, const std::vector<double>& ha,
                 const std::vector<double>& hb, int from, int to) {
  const LayerRay& ra = m.rays[a];
  const LayerRay& rb = m.rays[b];
  const auto& ca = ra.nodes;
  const auto& cb = rb.nodes;
  const bool fan = ra.wall_node == rb.wall_node;
  const int curve = ra.curve;
  const int na = to >= 0 ? to : static_cast<int>(ca.size()) - 1, nb = to >= 0 ? to : static_cast<int>(cb.size()) - 1;
  if (fan && std::min(na, nb) == 0) return;  // a fan ray without layers: nothing beside it
  int i = from, j = from;
  if (fan && from == 0) {
    add_cell(m, split_quads, {ca[0], cb[1], ca[1], -1}, LayerCellKind::Fan, curve, 0);
    i = j = 1;
  }
  auto level = [&](int p, int q, double layer) {
    return std::abs(ha[p] - hb[q]) <= std::min(0.5 * layer, 0.3 * dist(m.nodes[ca[p]], m.nodes[cb[q]]));
  };
  while (i < na || j < nb) {
    bool advance_a = i < na, advance_b = j < nb;
    if (advance_a && advance_b) {
      const double layer = std::min(ha[i + 1] - ha[i], hb[j + 1] - hb[j]);
      if (!((i == from && j == from) || level(i, j, layer)) || !level(i + 1, j + 1, layer)) {
        advance_a = ha[i + 1] < hb[j + 1];
        advance_b = !advance_a;
      }
    }
    const int layer = std::max(i, j);
    if (advance_a && advance_b) {
      add_cell(m, split_quads, {ca[i], cb[j], cb[j + 1], ca[i + 1]}, fan ? LayerCellKind::Fan : LayerCellKind::Quad,
               curve, layer);
      ++i;
      ++j;
    } else if (advance_b) {
      add_cell(m, split_quads, {ca[i], cb[j], cb[j + 1], -1}, LayerCellKind::Transition, curve, layer);
      ++j;
    } else {
      add_cell(m, split_quads, {ca[i], cb[j], ca[i + 1], -1}, LayerCellKind::Transition, curve, layer);
      ++i;
    }
  }
}

// A chain's front (its rays [b, e)): an open chain's first column upwards, the tops, its last column
// downwards.
LayerFront chain_front(const LayerMesh& m, int b, int e, bool closed) {
  LayerFront front;
  front.closed = closed;
  auto push = [&](int node) {
    if (front.nodes.empty() || front.nodes.back() != node) front.nodes.push_back(node);
  };
  if (!closed)
    for (std::size_t j = 0; j + 1 < m.rays[b].nodes.size(); ++j) push(m.rays[b].nodes[j]);
  for (int k = b; k < e; ++k)
    if (!m.rays[k].merged) push(m.rays[k].nodes.back());
  if (!closed)
    for (std::size_t j = m.rays[e - 1].nodes.size(); j-- > 0;) push(m.rays[e - 1].nodes[j]);
  if (closed && front.nodes.size() > 1 && front.nodes.front() == front.nodes.back()) front.nodes.pop_back();
  return front;
}

LayerMesh assemble(const RaySet& set, const std::vector<int>& count, const std::vector<double>& top,
                   const LayerSettings& settings, std::vector<int>& owner) {
  LayerMesh m;
  m.nodes = set.wall_points;
  m.wall_nodes = static_cast<int>(m.nodes.size());
  m.rays = set.rays;
  m.chain_ray_begin = set.ray_begin;
  m.chain_closed = set.closed;
  m.fan_sizes = set.fan_sizes;
  owner.assign(m.nodes.size(), -1);
  std::vector<std::vector<double>> height = ray_heights(count, top, settings);
  // Fans of two elements come from the ray tilt limit (the triangles' small fans); their middle ray
  // may end at its last layer where the front is as dense as the wall refinement makes it.
  const double fan_span = settings.max_ray_tilt_deg > 0.0 ? settings.split_span : 0.0;
  const ColumnPlan plan = plan_columns(set, height, settings.merge_span, fan_span);
  place_ray_nodes(m, count, top, plan.end, settings, height, owner);
  for (const ColumnPair& p : plan.pairs)
    zip_columns(m, settings.split_quads, p.a, p.b, height[p.a], height[p.b], p.from, p.to);
  // A merged column's last node b_k under its neighbours' nodes l_k+1, r_k+1: three triangles.
  for (const ColumnMerge& g : plan.merges) {
    const auto node = [&](int ray, int k) { return m.rays[ray].nodes[static_cast<std::size_t>(k)]; };
    const int k = g.layer, curve = m.rays[g.ray].curve;
    add_cell(m, false, {node(g.left, k), node(g.ray, k), node(g.left, k + 1), -1}, LayerCellKind::Transition, curve, k);
    add_cell(m, false, {node(g.ray, k), node(g.right, k), node(g.right, k + 1), -1}, LayerCellKind::Transition, curve,
             k);
    add_cell(m, false, {node(g.ray, k), node(g.right, k + 1), node(g.left, k + 1), -1}, LayerCellKind::Transition,
             curve, k);
  }
  for (std::size_t c = 0; c + 1 < set.ray_begin.size(); ++c)
    m.fronts.push_back(chain_front(m, set.ray_begin[c], set.ray_begin[c + 1], set.closed[c] != 0));
  return m;
}

// The distance from p to the segment a -> b.
double point_segment_distance(Vec2 p, Vec2 a, Vec2 b) {
  const Vec2 d = b - a;
  const double l2 = dot(d, d);
  const double t = l2 > 0.0 ? std::clamp(dot(p - a, d) / l2, 0.0, 1.0) : 0.0;
  return dist(p, a + t * d);
}

// The rays to shrink: those owning a node of an inverted cell, or of a cell edge that meets another
// cell edge (not at a shared node) or a curve of the geometry (not at the wall node it starts from).
std::vector<int> check(const LayerMesh& m, const std::vector<int>& owner, const Geometry& geometry) {
  std::vector<std::uint8_t> bad(m.rays.size(), 0);
  auto mark = [&](int node) {
    if (owner[node] >= 0) bad[owner[node]] = 1;
  };
  std::unordered_set<std::uint64_t> seen;
  std::vector<std::array<int, 2>> edges;
  for (const LayerCell& cell : m.cells) {
    const int k = cell.triangle() ? 3 : 4;
    bool ok = true;
    for (int i = 0; i < k; ++i)
      if (orient2d(m.nodes[cell.v[(i + k - 1) % k]], m.nodes[cell.v[i]], m.nodes[cell.v[(i + 1) % k]]) <= 0.0)
        ok = false;
    if (!ok)
      for (int i = 0; i < k; ++i) mark(cell.v[i]);
    for (int i = 0; i < k; ++i) {
      const int a = std::min(cell.v[i], cell.v[(i + 1) % k]), b = std::max(cell.v[i], cell.v[(i + 1) % k]);
      if (b < m.wall_nodes) continue;  // a wall edge: a segment of the geometry
      if (seen.insert((static_cast<std::uint64_t>(a) << 32) | static_cast<std::uint32_t>(b)).second)
        edges.push_back({a, b});
    }
  }
  Box box;
  double total = 0.0;
  for (const auto& e : edges) {
    box.add(m.nodes[e[0]]);
    box.add(m.nodes[e[1]]);
    total += dist(m.nodes[e[0]], m.nodes[e[1]]);
  }
  if (edges.empty()) return {};
  const int ne = static_cast<int>(edges.size());
  SegmentGrid grid(box, 2.0 * total / ne);
  for (int i = 0; i < ne; ++i) grid.insert(i, m.nodes[edges[i][0]], m.nodes[edges[i][1]]);
  const int ns = static_cast<int>(geometry.segments.size());
  for (int s = 0; s < ns; ++s) grid.insert(ne + s, geometry.segments[s].a, geometry.segments[s].b);
  for (int i = 0; i < ne; ++i) {
    const int a = edges[i][0], b = edges[i][1];
    const Vec2 pa = m.nodes[a], pb = m.nodes[b];
    grid.query(pa, pb, [&](int id) {
      if (id < ne) {
        if (id <= i) return;
        const int c = edges[id][0], d = edges[id][1];
        if (c == a || c == b || d == a || d == b) return;
        if (!segments_intersect(pa, pb, m.nodes[c], m.nodes[d])) return;
        for (const int v : {a, b, c, d}) mark(v);
        return;
      }
      const Segment& s = geometry.segments[id - ne];
      // An end ray's column lies on the segment it runs along: its own edges, and edges from its
      // nodes to nodes on the domain side of that segment, only touch it.
      auto on_ray = [&](int node, int r) {
        return node < m.wall_nodes ? node == m.rays[r].wall_node : owner[node] == r;
      };
      for (const int r : {a < m.wall_nodes ? -1 : owner[a], b < m.wall_nodes ? -1 : owner[b]}) {
        if (r < 0 || m.rays[r].slide_segment != id - ne) continue;
        const int other = on_ray(a, r) ? b : a;
        if (on_ray(other, r)) return;
        const int neighbour = std::binary_search(m.chain_ray_begin.begin(), m.chain_ray_begin.end(), r) ? r + 1 : r - 1;
        const double inside = orient2d(s.a, s.b, m.nodes[m.rays[neighbour].wall_node]);
        const double side = orient2d(s.a, s.b, m.nodes[other]);
        if ((inside > 0 && side > 0) || (inside < 0 && side < 0)) return;
      }
      // A wall node touches the segments it lies on (their ends, or inside one the wall was refined on).
      for (const Vec2 w : {pa, pb})
        if ((a < m.wall_nodes && w == pa) || (b < m.wall_nodes && w == pb))
          if (s.a == w || s.b == w || point_segment_distance(w, s.a, s.b) <= 1e-12 * s.length) return;
      if (!segments_intersect(pa, pb, s.a, s.b)) return;
      mark(a);
      mark(b);
    });
  }
  std::vector<int> out;
  for (std::size_t r = 0; r < bad.size(); ++r)
    if (bad[r]) out.push_back(static_cast<int>(r));
  return out;
}

}  // namespace

namespace {

// The end rays of open chains at the tied wall nodes, as pairs of ray indices.
std::vector<std::array<int, 2>> tied_rays(const RaySet& set, const std::vector<TiedEnds>& tied) {
  const auto at = [&set](Vec2 p) {
    for (std::size_t c = 0; c + 1 < set.ray_begin.size(); ++c) {
      if (set.closed[c] != 0 || set.ray_begin[c + 1] <= set.ray_begin[c]) continue;
      for (const int r : {set.ray_begin[c], set.ray_begin[c + 1] - 1})
        if (set.wall_points[static_cast<std::size_t>(set.rays[static_cast<std::size_t>(r)].wall_node)] == p) return r;
    }
    throw Error(fmt::format("boundary layer: no open wall chain ends at ({}, {}) (a tied end)", p.x, p.y));
  };
  std::vector<std::array<int, 2>> out;
  for (const TiedEnds& t : tied) out.push_back({at(t.a), at(t.b)});
  return out;
}

// Grades the thicknesses and gives each tied pair the smaller of its two, until neither changes them.
void grade_tied(const RaySet& set, const LayerSettings& settings, const std::vector<std::array<int, 2>>& ties,
                std::vector<double>& allowed) {
  for (int round = 0; round < 8; ++round) {
    grade_thickness(set, settings, allowed);
    bool changed = false;
    for (const auto& [a, b] : ties) {
      const double t = std::min(allowed[static_cast<std::size_t>(a)], allowed[static_cast<std::size_t>(b)]);
      changed = changed || allowed[static_cast<std::size_t>(a)] != t || allowed[static_cast<std::size_t>(b)] != t;
      allowed[static_cast<std::size_t>(a)] = allowed[static_cast<std::size_t>(b)] = t;
    }
    if (!changed) return;
  }
}

}  // namespace

int end_ray_at(const LayerMesh& layers, Vec2 p) {
  for (std::size_t c = 0; c + 1 < layers.chain_ray_begin.size(); ++c) {
    if (layers.chain_closed[c] != 0 || layers.chain_ray_begin[c + 1] <= layers.chain_ray_begin[c]) continue;
    for (const int r : {layers.chain_ray_begin[c], layers.chain_ray_begin[c + 1] - 1})
      if (layers.nodes[static_cast<std::size_t>(layers.rays[static_cast<std::size_t>(r)].wall_node)] == p) return r;
  }
  return -1;
}

LayerMesh build_boundary_layers(const Geometry& geometry, const std::vector<int>& wall_curves,
                                const LayerSettings& settings, const CoreSpacing& core_spacing,
                                const std::vector<TiedEnds>& tied) {
  check_layer_settings(settings);
  if (wall_curves.empty()) throw InputError("boundary layer: the list of wall curves is empty");
  for (const int c : wall_curves)
    if (c < 0 || c >= static_cast<int>(geometry.curves.size()))
      throw InputError(fmt::format("boundary layer: wall curve index {} is not a curve of the geometry (it has {})", c,
                                   geometry.curves.size()));
  std::vector<WallChain> chains = wall_chains(geometry, wall_curves);
  RaySet set = make_rays(chains, geometry, settings, core_spacing);
  std::vector<double> allowed;
  free_and_collision_limits(set, geometry, settings, core_spacing, allowed);
  refine_sparse_walls(chains, geometry, settings, core_spacing, set, allowed);
  leave_room_for_the_core(set, geometry, settings, allowed);
  const std::vector<std::array<int, 2>> ties = tied_rays(set, tied);
  std::vector<int> count, owner;
  std::vector<double> top;
  constexpr int kMaxRepairs = 60;
  for (int round = 0; round <= kMaxRepairs; ++round) {
    grade_tied(set, settings, ties, allowed);
    layer_counts(set, settings, allowed, count, top);
    LayerMesh m = assemble(set, count, top, settings, owner);
    const std::vector<int> bad = check(m, owner, geometry);
    if (bad.empty()) {
      m.repairs = round;
      return m;
    }
    for (const int r : bad) allowed[r] *= 0.7;
  }
  throw Error(fmt::format("boundary layer: cells still invalid after {} rounds of shrinking", kMaxRepairs));
}

}  // namespace pdmesh
