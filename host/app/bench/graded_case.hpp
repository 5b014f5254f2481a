// The generated benchmark case graded_1m of `pdmesh bench`: a square around a tiny circle, spacing
// (eq. 3.6) graded 1000x, with the far-field spacing chosen so the initial distribution has about
// the requested number of nodes (the fit below; tests/test_graded_case.cpp checks it).
#pragma once
#include <cstddef>

#include "geometry/geometry.hpp"

namespace pdmesh {

// Nodes of the initial distribution for far-field spacing h_out: a / h^2 + b / h, fitted to the
// counts measured at 12k..309k nodes (2026-11; within 1.5% there).
double graded_case_node_estimate(double h_out);

// The far-field spacing whose estimate is `target` nodes (the positive root of the fit).
double graded_case_spacing(std::size_t target);

// The geometry: a 20 x 20 square (sides split at spacing h_out) around a 256-segment circle of
// segment length h_out / 1000.
Geometry graded_case_geometry(double h_out);

}  // namespace pdmesh
