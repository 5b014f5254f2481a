// The node-count estimate over the background field's leaves; see node_estimate.hpp.
#include "init/node_estimate.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "core/parallel.hpp"

namespace pdmesh {
namespace {

// Nodes per unit area in hexagonal packing at spacing q is 2 / (sqrt(3) q^2).
const double kHexFactor = 2.0 / std::sqrt(3.0);

// A boundary sub-quad is split while it would hold more than this many nodes and the boundary
// may cut it. On the last level its inside fraction is taken from the signed distance d of its
// centre to the boundary, 1/2 + d / side (clamped): exact for a straight boundary parallel to a side,
// and for any straight boundary through the centre.
constexpr double kBoundaryNodes = 0.02;
constexpr int kBoundaryMaxDepth = 10;

struct LeafBox {
  double x0, y0, side;  // world coordinates of the low corner and the side
};

// The box of leaf `leaf` from its cell record (top cell, level, integer position).
LeafBox leaf_box(const BackgroundFieldData& d, int leaf) {
  const std::int32_t* c = &d.leaf_cell[4 * static_cast<std::size_t>(leaf)];
  const int gx = c[0] % d.grid, gy = c[0] / d.grid;
  const double side = std::ldexp(d.root_size, -c[1]);
  return {d.origin_x + d.root_size * gx + side * c[2], d.origin_y + d.root_size * gy + side * c[3], side};
}

// q of the leaf's bilinear at (u, v) in [0, 1]^2.
struct Bilinear {
  double q00, q10, q01, q11;
  double at(double u, double v) const { return (1 - v) * ((1 - u) * q00 + u * q10) + v * ((1 - u) * q01 + u * q11); }
};

// Nodes in the sub-rectangle [u0, u1] x [v0, v1] of a leaf of the given side (exact for the bilinear).
double sub_integral(const Bilinear& q, double side, double u0, double v0, double u1, double v1) {
  const double area = side * side * (u1 - u0) * (v1 - v0);
  return kHexFactor * area * inverse_square_integral(q.at(u0, v0), q.at(u1, v0), q.at(u0, v1), q.at(u1, v1));
}

// The part of a boundary leaf's sub-quad that is inside the domain.
double boundary_part(const GeometryTree& tree, const Bilinear& q, const LeafBox& leaf, double u0, double v0, double h,
                     int depth) {
  const double side = leaf.side * h;
  const Vec2 centre{leaf.x0 + leaf.side * (u0 + 0.5 * h), leaf.y0 + leaf.side * (v0 + 0.5 * h)};
  const double nodes = kHexFactor * side * side / (q.at(u0 + 0.5 * h, v0 + 0.5 * h) * q.at(u0 + 0.5 * h, v0 + 0.5 * h));
  // Farther from every segment than the half diagonal: nothing cuts the sub-quad, its centre decides.
  // (Embedded constraints cut nothing off: the boundary curves' segments alone.)
  const double distance = tree.closest_wall(centre).distance;
  if (distance > 0.7072 * side) return tree.inside(centre) ? sub_integral(q, leaf.side, u0, v0, u0 + h, v0 + h) : 0.0;
  if (nodes > kBoundaryNodes && depth < kBoundaryMaxDepth) {
    const double k = 0.5 * h;
    return boundary_part(tree, q, leaf, u0, v0, k, depth + 1) + boundary_part(tree, q, leaf, u0 + k, v0, k, depth + 1) +
           boundary_part(tree, q, leaf, u0, v0 + k, k, depth + 1) +
           boundary_part(tree, q, leaf, u0 + k, v0 + k, k, depth + 1);
  }
  const double signed_distance = tree.inside(centre) ? distance : -distance;
  const double fraction = std::clamp(0.5 + signed_distance / side, 0.0, 1.0);
  return fraction * sub_integral(q, leaf.side, u0, v0, u0 + h, v0 + h);
}

}  // namespace

namespace {

// The leaf's bilinear q, or false for a leaf that holds no nodes (outside, or no positive spacing).
bool leaf_q(const BackgroundFieldData& d, std::size_t leaf, Bilinear& q) {
  if (d.leaf_tag[leaf] == kTagOutside) return false;
  const std::int32_t* c = &d.leaf_corner[4 * leaf];
  q = {d.corner_q[static_cast<std::size_t>(c[0])], d.corner_q[static_cast<std::size_t>(c[1])],
       d.corner_q[static_cast<std::size_t>(c[2])], d.corner_q[static_cast<std::size_t>(c[3])]};
  return q.q00 > 0.0 && q.q10 > 0.0 && q.q01 > 0.0 && q.q11 > 0.0;  // no spacing there: no nodes
}

// Leaves per chunk of the parallel pass: an inside leaf is one closed form (~20 ns), a boundary leaf
// a few closest-segment and inside queries (~us); 30P30N's 128k leaves make 31 chunks.
constexpr std::size_t kLeavesPerChunk = 4096;

}  // namespace

double estimate_node_count(const GeometryTree& tree, const BackgroundSpacing& field) {
  const BackgroundFieldData& d = field.data();
  // Each leaf's nodes are computed on all cores (the boundary leaves' geometry queries take 0.04 s on
  // one core for 30P30N's curves alone, twice per run), then summed here in leaf order: the same
  // additions in the same order as one loop, so the estimate is the same bits whatever the thread count.
  std::vector<double> nodes(d.leaves(), 0.0);
  parallel_for(
      d.leaves(),
      [&](std::size_t leaf) {
        Bilinear q;
        if (!leaf_q(d, leaf, q)) return;
        const LeafBox box = leaf_box(d, static_cast<int>(leaf));
        nodes[leaf] = d.leaf_tag[leaf] == kTagInside ? sub_integral(q, box.side, 0.0, 0.0, 1.0, 1.0)
                                                     : boundary_part(tree, q, box, 0.0, 0.0, 1.0, 0);
      },
      kLeavesPerChunk);
  // A leaf without nodes adds +0.0, which leaves the sum's bits as skipping it did.
  double sum = 0.0;
  for (const double v : nodes) sum += v;
  return sum;
}

double node_count_bound(const BackgroundSpacing& field) {
  const BackgroundFieldData& d = field.data();
  double sum = 0.0;
  Bilinear q;
  for (std::size_t leaf = 0; leaf < d.leaves(); ++leaf)
    if (leaf_q(d, leaf, q)) sum += sub_integral(q, leaf_box(d, static_cast<int>(leaf)).side, 0.0, 0.0, 1.0, 1.0);
  return sum;
}

}  // namespace pdmesh
