// Closing the seams between the hybrid fill's lattices of different spacing levels.
#pragma once
#include <cstddef>

#include "geometry/geometry_tree.hpp"
#include "init/quad_fill.hpp"
#include "nodes/node_set.hpp"
#include "spacing/spacing_field.hpp"

namespace pdmesh {

// Each lattice stops at the edge of its quad, so where a quad of one level meets a quad of another (or a
// pattern quad) the rows of the two sides end at arbitrary distances from the edge: gaps of up to two rows
// that population control later fills. For every quad of state.level_quads, in the fill's order, the points
// of its lattice one row or column beyond its box are candidates: one that no node lies within 0.6 h of (a
// hole) is added as an Interior node. Inside a region of one level the candidates are the neighbours' own
// lattice points and are skipped. Deterministic. Returns how many were added.
std::size_t close_lattice_seams(const GeometryTree& tree, const SpacingField& spacing, FillState& state,
                                NodeSet& nodes);

}  // namespace pdmesh
