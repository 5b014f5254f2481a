// The hexagonal-packing node-count estimate, integral of 2 / (sqrt(3) q^2) over the domain, in one
// pass over the leaves of the background spacing field: exact for its bilinear q in every inside
// leaf, and in boundary leaves over sub-quads that the boundary does not cut (found by exact
// geometry tests down to a fraction of a node), so that it costs O(leaves), not spacing queries
// per sample (docs/initialization.md, "Estimate").
#pragma once
#include "geometry/geometry_tree.hpp"
#include "spacing/background_field.hpp"

namespace pdmesh {

// Integral over [0,1]^2 of 1 / q(u, v)^2 for q bilinear with corners q00, q10 (u = 1), q01 (v = 1),
// q11, all positive: closed form (one logarithm), a series where the logarithm would cancel.
double inverse_square_integral(double q00, double q10, double q01, double q11);

// Computed on all cores; the same value as a single-threaded loop over the leaves, bit for bit.
double estimate_node_count(const GeometryTree& tree, const BackgroundSpacing& field);

// The same integral with every leaf that is not outside counted whole: not below estimate_node_count
// but for rounding (a boundary leaf's estimate is a part of its whole integral), in one pass with no
// geometry query. For checks that only need to know that the estimate stays below a limit.
double node_count_bound(const BackgroundSpacing& field);

}  // namespace pdmesh
