// The Hessian of a scalar u: by central differences of a function, or recovered from values at the
// points of a triangle mesh by a least-squares quadratic fit over each vertex's patch (exact when u
// is a quadratic). The input of the Hessian metric (spacing/hessian_metric.hpp).
#pragma once
#include <array>
#include <functional>
#include <string_view>
#include <vector>

#include "core/vec2.hpp"

namespace pdmesh {

// A symmetric 2x2 matrix of second derivatives (not necessarily definite).
struct Hessian {
  double xx = 0.0;
  double xy = 0.0;
  double yy = 0.0;
};

// Second-order central differences with step h: u_xx from u(p ± h e_x), u_xy from the four diagonal
// neighbours. Exact for quadratics up to rounding, error O(h²) otherwise.
Hessian hessian_by_differences(const std::function<double(Vec2)>& u, Vec2 p, double h);

// The Hessian at every point of a triangle mesh from values u at its points. Each vertex's patch is
// its neighbours through the triangles, grown by a ring at a time (up to four) while it has too few
// points or they do not determine a quadratic (collinear, or on a conic through the vertex); the
// quadratic u(p) = c + g·d + dᵀ H d / 2 (d = p - vertex) is fitted to the patch and the vertex by least
// squares (Householder QR, coordinates scaled by the patch's radius). A point in no triangle gets a
// zero Hessian. Throws InputError naming `what`, the point and the value for a value that is not
// finite, and naming the vertex when no ring up to the fourth determines a quadratic. u.size() must
// equal points.size() and every triangle index lie in [0, points.size()) (the callers' data, as the
// mesh readers check it).
std::vector<Hessian> recover_hessians(const std::vector<Vec2>& points, const std::vector<std::array<int, 3>>& triangles,
                                      const std::vector<double>& u, std::string_view what);

}  // namespace pdmesh
