// planar_faces(): traces the faces of a planar graph with half-edges (each vertex's edges sorted by
// angle, a face walked by turning to the next edge clockwise), then places each connected
// component's outside in the innermost face of another component that contains it.
#include "geometry/planar_faces.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "core/predicates.hpp"

namespace pdmesh {
namespace {

// Crossing parity of the ray from p towards +x with the closed polygon `cycle` (exact; p on no edge).
bool inside_cycle(const std::vector<Vec2>& vertices, const std::vector<int>& cycle, Vec2 p) {
  bool in = false;
  for (std::size_t k = 0; k < cycle.size(); ++k) {
    const Vec2 a = vertices[cycle[k]], b = vertices[cycle[(k + 1) % cycle.size()]];
    if ((a.y > p.y) == (b.y > p.y)) continue;
    const double o = orient2d(a, b, p);
    if (b.y > a.y ? o > 0 : o < 0) in = !in;
  }
  return in;
}

bool on_edge(Vec2 a, Vec2 b, Vec2 p) {
  if (orient2d(a, b, p) != 0.0) return false;
  return std::min(a.x, b.x) <= p.x && p.x <= std::max(a.x, b.x) && std::min(a.y, b.y) <= p.y &&
         p.y <= std::max(a.y, b.y);
}

int find_root(std::vector<int>& parent, int v) {
  while (parent[v] != v) v = parent[v] = parent[parent[v]];
  return v;
}

// The innermost bounded face whose outer boundary holds p strictly inside, -1 for none; faces
// listed in `skip_component` (those of p's own component) are not considered.
int innermost(const PlanarFaces& f, const std::vector<Vec2>& vertices, const std::vector<int>& face_component,
              int skip_component, Vec2 p) {
  int best = -1;
  for (int k = 0; k < static_cast<int>(f.outer.size()); ++k) {
    if (face_component[k] == skip_component) continue;
    if (best >= 0 && f.outer_area[k] >= f.outer_area[best]) continue;
    if (f.outer_box[k].contains(p) && inside_cycle(vertices, f.outer[k], p)) best = k;
  }
  return best;
}

}  // namespace

PlanarFaces planar_faces(const std::vector<Vec2>& vertices, const std::vector<std::array<int, 2>>& edges) {
  const int nh = 2 * static_cast<int>(edges.size());
  auto origin = [&](int h) { return edges[h / 2][h % 2]; };
  auto dest = [&](int h) { return edges[h / 2][1 - h % 2]; };

  // Outgoing half-edges per vertex, counter-clockwise by angle.
  std::vector<std::vector<int>> out(vertices.size());
  for (int h = 0; h < nh; ++h) out[origin(h)].push_back(h);
  std::vector<int> slot(nh, 0);
  for (auto& list : out) {
    std::vector<double> angle(list.size());
    for (std::size_t i = 0; i < list.size(); ++i) {
      const Vec2 d = vertices[dest(list[i])] - vertices[origin(list[i])];
      angle[i] = std::atan2(d.y, d.x);
    }
    std::vector<std::size_t> order(list.size());
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(), [&](std::size_t i, std::size_t j) { return angle[i] < angle[j]; });
    std::vector<int> sorted;
    for (const std::size_t i : order) sorted.push_back(list[i]);
    list = std::move(sorted);
    for (std::size_t i = 0; i < list.size(); ++i) slot[list[i]] = static_cast<int>(i);
  }
  // The face on the left of h continues with the edge clockwise next to h's twin at h's end.
  auto next = [&](int h) {
    const auto& around = out[dest(h)];
    const int n = static_cast<int>(around.size());
    return around[(slot[h ^ 1] + n - 1) % n];
  };

  std::vector<int> cycle_of(nh, -1);
  std::vector<std::vector<int>> cycles;  // vertex indices along each cycle
  std::vector<double> area;
  for (int h0 = 0; h0 < nh; ++h0) {
    if (cycle_of[h0] >= 0) continue;
    const int c = static_cast<int>(cycles.size());
    std::vector<int> cycle;
    const Vec2 ref = vertices[origin(h0)];
    double twice = 0.0;
    for (int h = h0; cycle_of[h] < 0; h = next(h)) {
      cycle_of[h] = c;
      cycle.push_back(origin(h));
      twice += cross(vertices[origin(h)] - ref, vertices[dest(h)] - ref);
    }
    cycles.push_back(std::move(cycle));
    area.push_back(0.5 * twice);
  }

  // Connected components; the cycle of least signed area in each is its outside (clockwise, or
  // the walk around a tree), every other one bounds a face of its own.
  std::vector<int> parent(vertices.size());
  std::iota(parent.begin(), parent.end(), 0);
  for (const auto& e : edges) parent[find_root(parent, e[0])] = find_root(parent, e[1]);
  const int nc = static_cast<int>(cycles.size());
  std::vector<int> component(nc), outside_of(vertices.size(), -1);
  for (int c = 0; c < nc; ++c) {
    component[c] = find_root(parent, cycles[c][0]);
    int& o = outside_of[component[c]];
    if (o < 0 || area[c] < area[o]) o = c;
  }
  PlanarFaces f;
  std::vector<int> face_of_cycle(nc, -1), face_component;
  for (int c = 0; c < nc; ++c) {
    if (outside_of[component[c]] == c) continue;
    face_of_cycle[c] = static_cast<int>(f.outer.size());
    f.outer.push_back(cycles[c]);
    Box box;
    for (const int v : cycles[c]) box.add(vertices[v]);
    f.outer_box.push_back(box);
    f.outer_area.push_back(area[c]);
    face_component.push_back(component[c]);
  }
  for (int c = 0; c < nc; ++c) {
    if (outside_of[component[c]] != c) continue;
    face_of_cycle[c] = innermost(f, vertices, face_component, component[c], vertices[cycles[c][0]]);
  }
  f.sides.resize(edges.size());
  for (std::size_t e = 0; e < edges.size(); ++e)
    f.sides[e] = {face_of_cycle[cycle_of[2 * e]], face_of_cycle[cycle_of[2 * e + 1]]};
  return f;
}

int locate_face(const PlanarFaces& faces, const std::vector<Vec2>& vertices,
                const std::vector<std::array<int, 2>>& edges, Vec2 p) {
  for (const auto& e : edges)
    if (on_edge(vertices[e[0]], vertices[e[1]], p)) return -2;
  int best = -1;
  for (int k = 0; k < static_cast<int>(faces.outer.size()); ++k) {
    if (best >= 0 && faces.outer_area[k] >= faces.outer_area[best]) continue;
    if (faces.outer_box[k].contains(p) && inside_cycle(vertices, faces.outer[k], p)) best = k;
  }
  return best;
}

}  // namespace pdmesh
