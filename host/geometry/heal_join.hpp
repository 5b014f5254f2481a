// The "joined" healing rule (docs/geometry-input.md, "Healing"): two closed curves that touch or
// overlap in one place (OGC polygons let a hole touch its outer ring or another hole at a point; merged
// GIS polygons overlap a little) are one ring through a neck about h wide. Internal to heal.cpp.
#pragma once
#include <functional>
#include <optional>
#include <utility>
#include <vector>

#include "core/vec2.hpp"

namespace pdmesh::detail {

struct JoinedRings {
  std::vector<Vec2> ring;                   // the joined ring (no repeated last point)
  std::vector<std::pair<int, int>> origin;  // per point: (0 for a, 1 for b; the vertex it is or follows)
  std::vector<Vec2> removed, added;         // the parts inside the neck's disc, and the two chords
  Vec2 centre;                              // the middle of where they meet
  double radius = 0.0;                      // the disc cut out around it
  double h = 0.0;
};

// Rings a and b (closed, no repeated last point) are both oriented with the domain on their left.
// Where they meet (touch or cross) within `h(p)` of the middle p of the meeting points, a disc of
// radius 0.5 h + that spread around p is cut out of both and the two open chains left are joined by
// two chords across it: a runs into b and b back into a, which keeps the domain on the left (the
// union of what lies outside the domain on both sides: a hole becomes a bay of the outer ring). Null
// when they do not meet, meet in more than one place, either ring crosses the disc more than once,
// or the chords would cross the joined ring.
std::optional<JoinedRings> join_rings(const std::vector<Vec2>& a, const std::vector<Vec2>& b,
                                      const std::function<double(Vec2)>& h);

}  // namespace pdmesh::detail
