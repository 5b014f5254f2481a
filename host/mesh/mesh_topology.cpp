// Folds and non-manifold edges of a triangle mesh (see mesh_topology.hpp).
#include "mesh/mesh_topology.hpp"

#include <algorithm>
#include <cstdint>
#include <vector>

#include <fmt/format.h>

namespace pdmesh {
namespace {

struct KeyedEdgeUse {
  std::uint64_t key;  // (smaller point << 32) | larger point
  int triangle;
  bool forward;  // the triangle runs from the smaller point to the larger
};

}  // namespace

std::optional<std::string> find_fold_or_nonmanifold_edge(const Mesh& mesh) {
  std::vector<KeyedEdgeUse> uses;
  uses.reserve(3 * mesh.triangles.size());
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const auto& v = mesh.triangles[t];
    for (int k = 0; k < 3; ++k) {
      const int a = v[k], b = v[(k + 1) % 3];
      if (a == b) continue;  // a degenerate triangle: measured as such
      const auto lo = static_cast<std::uint64_t>(std::min(a, b)), hi = static_cast<std::uint64_t>(std::max(a, b));
      uses.push_back({lo << 32 | hi, static_cast<int>(t), a < b});
    }
  }
  std::sort(uses.begin(), uses.end(), [](const KeyedEdgeUse& x, const KeyedEdgeUse& y) {
    return x.key != y.key ? x.key < y.key : x.triangle < y.triangle;
  });
  // The conflict to report: the one whose second triangle is earliest in the file.
  std::size_t best = uses.size();
  int best_second = 0;
  bool best_fold = false;
  for (std::size_t i = 0; i < uses.size();) {
    std::size_t j = i + 1;
    while (j < uses.size() && uses[j].key == uses[i].key) ++j;
    const std::size_t n = j - i;
    const bool fold = n == 2 && uses[i].forward == uses[i + 1].forward;
    if ((fold || n > 2) && (best == uses.size() || uses[i + 1].triangle < best_second)) {
      best = i;
      best_second = uses[i + 1].triangle;
      best_fold = fold;
    }
    i = j;
  }
  if (best == uses.size()) return std::nullopt;
  const auto a = static_cast<int>(uses[best].key >> 32), b = static_cast<int>(uses[best].key & 0xffffffffu);
  const auto tri = [&](int t) {
    const auto& v = mesh.triangles[static_cast<std::size_t>(t)];
    return fmt::format("triangle {} (points {}, {}, {})", t, v[0], v[1], v[2]);
  };
  const auto point = [&](int p) {
    const Vec2 x = mesh.points[static_cast<std::size_t>(p)];
    return fmt::format("{} ({}, {})", p, x.x, x.y);
  };
  const std::string edge = fmt::format("the edge between points {} and {}", point(a), point(b));
  if (best_fold) {
    return fmt::format(
        "{} and {} lie on the same side of {}: one is folded over the other (a triangle inverted in "
        "the file, or overlapping triangles)",
        tri(uses[best].triangle), tri(uses[best + 1].triangle), edge);
  }
  return fmt::format(
      "{} belongs to more than two triangles, among them {}, {} and {}: the mesh is not a manifold there", edge,
      tri(uses[best].triangle), tri(uses[best + 1].triangle), tri(uses[best + 2].triangle));
}

}  // namespace pdmesh
