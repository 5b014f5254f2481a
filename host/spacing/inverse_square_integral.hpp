// The integral of 1 / q^2 over a unit cell with bilinear q: the hexagonal-packing node count of a cell
// (2 / (sqrt(3) q^2) nodes per unit area), used by the node estimate (init/node_estimate) and by the
// spacing quadtree's node budget while it is built (spacing/background_builder, limited_field).
#pragma once

namespace pdmesh {

// Integral over [0,1]^2 of 1 / q(u, v)^2 for q bilinear with corners q00, q10 (u = 1), q01 (v = 1),
// q11, all positive: closed form (one logarithm), a series where the logarithm would cancel.
double inverse_square_integral(double q00, double q10, double q01, double q11);

}  // namespace pdmesh
