// The hexagonal-packing node-count estimate, integral of 2 / (sqrt(3) q^2) over the domain, in one
// pass over the leaves of the background spacing field: exact for its bilinear q in every inside
// leaf, and in boundary leaves over sub-quads that the boundary does not cut (found by exact
// geometry tests down to a fraction of a node), so that it costs O(leaves), not spacing queries
// per sample (docs/initialization.md, "Estimate").
#pragma once
#include "geometry/geometry_tree.hpp"
#include "spacing/background_field.hpp"
#include "spacing/inverse_square_integral.hpp"

namespace pdmesh {

// Computed on all cores; the same value as a single-threaded loop over the leaves, bit for bit.
double estimate_node_count(const GeometryTree& tree, const BackgroundSpacing& field);

// The same integral with every leaf that is not outside counted whole: not below estimate_node_count
// but for rounding (a boundary leaf's estimate is a part of its whole integral), in one pass with no
// geometry query. For checks that only need to know that the estimate stays below a limit.
double node_count_bound(const BackgroundSpacing& field);

}  // namespace pdmesh
