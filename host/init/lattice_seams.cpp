// Closing the seams between the hybrid fill's lattices: candidates one ring beyond each lattice quad, kept in holes.
#include "init/lattice_seams.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <unordered_map>
#include <vector>

namespace pdmesh {

namespace {

// A candidate fills a hole when no node is nearer than this many lattice spacings h. In the lattice the
// nearest node is h away; across a seam the rows of the two sides lie 0-2 rows apart.
// Experiment knob (journal 2026-12-04c-seams): PDMESH_SEAM_TAU sets it, <= 0 turns the seam fill off.
double seam_clearance() {
  if (const char* s = std::getenv("PDMESH_SEAM_TAU")) return std::atof(s);
  return 0.6;
}

// The nodes by cell of a grid per octave of q: a node of spacing q in [2^(k-1), 2^k) sits in grid k,
// whose cells are 2^k wide; a query looks into the grids of the octaves around its own.
class NodeGrid {
 public:
  NodeGrid(const NodeSet& nodes, Vec2 origin) : nodes_(nodes), origin_(origin) {
    cells_.reserve(nodes.size());
    for (std::size_t n = 0; n < nodes.size(); ++n) cells_.push_back({key_of(static_cast<int>(n)), static_cast<int>(n)});
    std::sort(cells_.begin(), cells_.end());
  }

  // Is any node (the grid's, or one added since) within r of p?
  bool any_within(Vec2 p, double r) const {
    const int k0 = octave(r);
    for (int k = k0 - 1; k <= k0 + 2; ++k) {
      const double cell = std::ldexp(1.0, k);
      const auto x_lo = static_cast<std::int64_t>(std::floor((p.x - r - origin_.x) / cell));
      const auto x_hi = static_cast<std::int64_t>(std::floor((p.x + r - origin_.x) / cell));
      const auto y_lo = static_cast<std::int64_t>(std::floor((p.y - r - origin_.y) / cell));
      const auto y_hi = static_cast<std::int64_t>(std::floor((p.y + r - origin_.y) / cell));
      for (std::int64_t iy = y_lo; iy <= y_hi; ++iy) {
        for (std::int64_t ix = x_lo; ix <= x_hi; ++ix) {
          const std::uint64_t key = pack(k, ix, iy);
          auto it = std::lower_bound(cells_.begin(), cells_.end(), Entry{key, -1});
          for (; it != cells_.end() && it->key == key; ++it)
            if (dist(nodes_.x[static_cast<std::size_t>(it->node)], p) < r) return true;
          const auto range = added_.equal_range(key);
          for (auto a = range.first; a != range.second; ++a)
            if (dist(nodes_.x[static_cast<std::size_t>(a->second)], p) < r) return true;
        }
      }
    }
    return false;
  }

  // A node appended to the set after the grid was built.
  void added(int n) { added_.emplace(key_of(n), n); }

 private:
  struct Entry {
    std::uint64_t key;
    int node;
    bool operator<(const Entry& o) const { return key < o.key || (key == o.key && node < o.node); }
  };

  static int octave(double q) { return static_cast<int>(std::floor(std::log2(q))) + 1; }
  static std::uint64_t pack(int k, std::int64_t ix, std::int64_t iy) {
    return (static_cast<std::uint64_t>(k + 512) << 54) | (static_cast<std::uint64_t>(ix & 0x7FFFFFF) << 27) |
           static_cast<std::uint64_t>(iy & 0x7FFFFFF);
  }
  std::uint64_t key_of(int n) const {
    const auto u = static_cast<std::size_t>(n);
    const double q = nodes_.q[u] > 0.0 && std::isfinite(nodes_.q[u]) ? nodes_.q[u] : 1.0;
    const int k = octave(q);
    const double cell = std::ldexp(1.0, k);
    return pack(k, static_cast<std::int64_t>(std::floor((nodes_.x[u].x - origin_.x) / cell)),
                static_cast<std::int64_t>(std::floor((nodes_.x[u].y - origin_.y) / cell)));
  }

  const NodeSet& nodes_;
  Vec2 origin_;
  std::vector<Entry> cells_;
  std::unordered_multimap<std::uint64_t, int> added_;
};

}  // namespace

std::size_t close_lattice_seams(const GeometryTree& tree, const SpacingField& spacing, FillState& state,
                                NodeSet& nodes) {
  const double clearance = seam_clearance();
  if (state.level_quads.empty() || clearance <= 0.0) return 0;
  const Vec2 origin = tree.geometry().extents.lo;
  NodeGrid grid(nodes, origin);
  std::size_t added = 0;
  for (const LevelQuad& quad : state.level_quads) {
    const LatticeSpan span = lattice_span(origin, quad.box, quad.h);
    for (std::int64_t j = span.j_lo - 1; j <= span.j_hi + 1; ++j) {
      const bool row_inside = j >= span.j_lo && j <= span.j_hi;
      const std::int64_t i_lo = span.i_lo(j), i_hi = span.i_hi(j);
      for (std::int64_t i = i_lo - 1; i <= i_hi + 1; ++i) {
        if (row_inside && i >= i_lo && i <= i_hi) continue;  // the quad's own point
        const std::uint64_t key = lattice_key(quad.level, i, j);
        if (state.lattice.count(key) != 0) continue;  // a neighbour of the same level placed it
        const Vec2 p = lattice_point(origin, quad.h, i, j);
        if (grid.any_within(p, clearance * quad.h)) continue;
        double q = 0.0;
        // The quad lies kHybridClearance q beyond its half-diagonal from the boundary: p is inside.
        if (!keep_interior_candidate(tree, spacing, p, true, q)) continue;
        state.lattice.insert(key);
        grid.added(nodes.add(p, q, NodeKind::Interior, -1));
        ++added;
      }
    }
  }
  return added;
}

}  // namespace pdmesh
