// Point sources that make the spacing field follow short stretches of boundary between two critical
// points (docs/spacing.md, "Short segments"): a blunt trailing edge closed by a segment 50x shorter
// than its neighbours has fixed nodes at both ends, and a field of the neighbours' size next to it
// gives a sliver there. With boundary nodes placed by the field, such an arc asks for q no larger
// than its length at both ends, and the gradation limit spreads it.
#pragma once
#include <vector>

#include "geometry/geometry.hpp"
#include "spacing/gradation.hpp"
#include "spacing/spacing_field.hpp"

namespace pdmesh {

// An arc between consecutive critical points of a curve is short when its length times this is below
// `scale` times the larger of the segments on either side of it and the base field at its ends and
// middle: the field the run places nodes by there (spacing.scale multiplies it).
inline constexpr double kShortArcRatio = 4.0;

// One source at each end of every short arc, with q its length (a source's q is not scaled: the arc's
// two fixed nodes are that far apart at any scale).
std::vector<PointSource> short_arc_sources(const Geometry& geometry, const SpacingField& base, double scale = 1.0);

}  // namespace pdmesh
