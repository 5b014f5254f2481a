// The refusal of geometries whose coordinates are too large for double precision to resolve at the
// segment lengths and spacings they ask for (before any large allocation; docs/robustness.md).
#pragma once
#include "geometry/geometry.hpp"
#include "spacing/spacing_field.hpp"

namespace pdmesh {

// Near a coordinate of magnitude M, doubles are M * 2^-52 apart (one quantum, to within a factor 2).
// The shortest segment and the smallest spacing must be at least this many quanta. Why 1e4: the
// default first move is q/200 (docs/simulation.md), which a quantum of q/1e4 still resolves to 2%;
// and the Lennard-Jones force goes as r^-13, so a relative error e in a neighbour distance makes a
// relative force error of about 13 e, which stays below 0.2% at e = 1e-4. A case at 1e12 with
// spacing 1e-3 (1.2e-4 per quantum, 8 quanta per spacing) is far beyond; the thesis' cases need
// about 1e-7 of this limit.
inline constexpr double kResolutionQuanta = 1e4;

// Throws LimitError naming the file and line of the largest coordinate and of the shortest segment
// (or the point where the smallest spacing was sampled), with the figures, when
// max |coordinate| * 2^-52 * kResolutionQuanta exceeds the shortest segment length or the
// smallest spacing sampled at the curve points and the extents' centre.
void check_coordinate_resolution(const Geometry& geometry, const SpacingField& spacing);

}  // namespace pdmesh
