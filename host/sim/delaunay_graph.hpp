// The Delaunay graph of a node set (population control's view of the nodes: sim/population_plan.cpp
// and its metric counterpart sim/metric_population_plan.cpp).
#pragma once
#include <algorithm>
#include <array>
#include <cstddef>
#include <vector>

#include "core/vec2.hpp"
#include "mesh/delaunay.hpp"
#include "sim/population_profile.hpp"

namespace pdmesh::population_detail {

// The Delaunay graph of the nodes (input indices), as sorted adjacency lists.
struct DelaunayGraph {
  std::vector<std::array<int, 3>> triangles;  // real triangles only (no super-triangle vertex)
  std::vector<std::size_t> first;             // node i's neighbours: adjacent[first[i] .. first[i + 1])
  std::vector<int> adjacent;
  std::vector<char> on_hull;  // joined to a super-triangle vertex

  explicit DelaunayGraph(const std::vector<Vec2>& points) : DelaunayGraph(triangulate(points)) {}
  // A triangulation made for the graph alone: the arrays the graph does not read (points, neighbours,
  // vertex maps) are freed before the graph's own are made (a population event's largest moment).
  explicit DelaunayGraph(Triangulation&& dt) : DelaunayGraph(static_cast<const Triangulation&>(keep_triangles(dt))) {}
  // The graph of a triangulation of the nodes (e.g. one flipped to the metric's Delaunay).
  explicit DelaunayGraph(const Triangulation& dt) {
    const population_profile::Timer timer("graph");
    const auto n = static_cast<std::size_t>(dt.input_count);
    on_hull.assign(n, 0);
    // Every side (a, b) with both ends real, of every triangle (the super-triangle's too): in a
    // triangulation each directed edge is the side of one triangle, the one on its left, so a gets
    // each neighbour b once from the sides a -> b.
    std::vector<std::size_t> count(n + 1, 0);
    triangles.reserve(dt.v.size());  // never grown by doubling: a million-node event's largest arrays
    for (const auto& tv : dt.v) {
      const bool super[3] = {dt.is_super(tv[0]), dt.is_super(tv[1]), dt.is_super(tv[2])};
      for (int k = 0; k < 3; ++k) {
        if (super[k]) continue;
        const int a = dt.input_index[static_cast<std::size_t>(tv[k])];
        if (super[(k + 1) % 3] || super[(k + 2) % 3]) on_hull[static_cast<std::size_t>(a)] = 1;
        if (!super[(k + 1) % 3]) ++count[static_cast<std::size_t>(a) + 1];
      }
      if (!super[0] && !super[1] && !super[2])
        triangles.push_back({dt.input_index[static_cast<std::size_t>(tv[0])],
                             dt.input_index[static_cast<std::size_t>(tv[1])],
                             dt.input_index[static_cast<std::size_t>(tv[2])]});
    }
    for (std::size_t i = 0; i < n; ++i) count[i + 1] += count[i];
    std::vector<int> all(count[n]);
    {
      std::vector<std::size_t> next(count.begin(), count.end() - 1);
      for (const auto& tv : dt.v)
        for (int k = 0; k < 3; ++k)
          if (!dt.is_super(tv[k]) && !dt.is_super(tv[(k + 1) % 3]))
            all[next[static_cast<std::size_t>(dt.input_index[static_cast<std::size_t>(tv[k])])]++] =
                dt.input_index[static_cast<std::size_t>(tv[(k + 1) % 3])];
    }
    // Sorted; a repeat (none in a valid triangulation) is dropped. Compacted in place (a list never
    // moves forward), count becoming the lists' starts: no second copy of the lists.
    std::size_t written = 0, b = 0;
    for (std::size_t i = 0; i < n; ++i) {
      const std::size_t e = count[i + 1];
      const auto lo = all.begin() + static_cast<std::ptrdiff_t>(b), end = all.begin() + static_cast<std::ptrdiff_t>(e);
      std::sort(lo, end);
      const auto hi = std::unique(lo, end);
      count[i] = written;
      if (written != b) std::copy(lo, hi, all.begin() + static_cast<std::ptrdiff_t>(written));  // written < b
      written += static_cast<std::size_t>(hi - lo);
      b = e;
    }
    count[n] = written;
    all.resize(written);
    adjacent = std::move(all);
    first = std::move(count);
  }

  static Triangulation triangulate(const std::vector<Vec2>& points) {
    const population_profile::Timer timer("triangulation");
    return Triangulation(points);
  }

  static Triangulation& keep_triangles(Triangulation& dt) {
    std::vector<Vec2>().swap(dt.points);
    std::vector<int>().swap(dt.vertex_of);
    std::vector<std::array<int, 3>>().swap(dt.n);
    std::vector<int>().swap(dt.vertex_triangle);
    return dt;
  }

  std::size_t valence(int i) const {
    return first[static_cast<std::size_t>(i) + 1] - first[static_cast<std::size_t>(i)];
  }
  const int* begin(int i) const { return adjacent.data() + first[static_cast<std::size_t>(i)]; }
  const int* end(int i) const { return adjacent.data() + first[static_cast<std::size_t>(i) + 1]; }

  // The node nearest to p by a greedy walk from `start`: in a Delaunay graph, a node none of whose
  // neighbours is closer to p is the nearest node of all.
  int nearest(const std::vector<Vec2>& x, Vec2 p, int start) const {
    int v = start;
    double best = norm2(x[static_cast<std::size_t>(v)] - p);
    for (;;) {
      int next = v;
      for (const int* u = begin(v); u != end(v); ++u) {
        const double d = norm2(x[static_cast<std::size_t>(*u)] - p);
        if (d < best) {
          best = d;
          next = *u;
        }
      }
      if (next == v) return v;
      v = next;
    }
  }
};

}  // namespace pdmesh::population_detail
