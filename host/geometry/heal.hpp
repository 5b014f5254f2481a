// Healing at the mesh's resolution (docs/geometry-input.md, "Healing"): before build_geometry, the
// raw boundary curves lose the details the mesh cannot resolve: vertices closer than a fraction of
// the local spacing merge, one-vertex spikes go, narrow inlets and narrow intrusions are cut off at
// their mouth, loops smaller than about h² are dropped, and closed curves that touch or overlap in one
// place (a hole touching the outer ring, as OGC polygons allow) are joined into one ring. Every change is recorded with
// what it removed and what it added, for the report, quality.json and healing.png.
#pragma once
#include <functional>
#include <string>
#include <vector>

#include "geometry/geometry.hpp"

namespace pdmesh {

struct HealOptions {
  // The local spacing h at a vertex is the median length of the kNeighbourhood input segments around
  // it along its curve, times `scale` (spacing.scale): eq. 3.6's spacing on the raw geometry, without
  // the outliers that healing is for. An island's h is the median of all input segments (times
  // `scale`). Merges judge by that median without `scale`: they remove outliers of the curve's own
  // sampling, which do not depend on the mesh's scale.
  double scale = 1.0;
  // The size the case states at a point (spacing.size, a spacing expression), when it states one:
  // h is then no larger than it (times `scale`), so that what the case asks to resolve is not healed
  // away.
  std::function<double(Vec2)> size;
  double merge_fraction = 0.25;  // consecutive vertices closer than this x h merge
  double width_fraction = 0.5;   // inlets and intrusions narrower than this x h are cut off
  // Loops with an area below this x h² are dropped: (0.25 h)², a loop narrower than the merge
  // distance, below the mesh's resolution; a larger one is a hole or island the field resolves.
  double area_fraction = 0.0625;
  double spike_angle_deg = 20.0;  // a vertex sharper than this whose neighbours continue the line is a spike
  // The hole points the input states (a .poly's holes): a loop that holds one is a hole the file
  // asks for, not an island, and is never dropped (its hole point would then lie in the domain).
  std::vector<Vec2> holes;
  double join_tolerance = 1e-9;  // GeometryOptions::join_tolerance: which curves close on themselves
  static constexpr int kNeighbourhood = 8;
};

enum class HealKind {
  Merge,        // two close vertices became one (their midpoint)
  Spike,        // a one-vertex spike removed
  InletClosed,  // a narrow part of the domain cut off at its mouth (the domain loses it)
  InletOpened,  // a narrow intrusion into the domain cut off at its mouth (the domain gains it)
  Island,       // a loop smaller than about h² dropped
  Joined,       // two closed curves that touch or overlap in one place became one ring through a neck
};
const char* to_string(HealKind kind);
inline constexpr int kHealKinds = 6;

struct HealChange {
  HealKind kind = HealKind::Merge;
  std::string curve;  // the curve's name (or "curve<k>" when it has none yet)
  std::string file;
  int line = 0;  // the source line of the first point concerned
  Vec2 at;       // where (the merged point, the spike's tip, the mouth's middle, a loop's first point)
  // The measure that made it a defect: merge the distance, spike the angle (degrees), inlet the
  // width at the mouth, island the area, joined the neck's radius.
  double size = 0.0;
  double h = 0.0;             // the local spacing it was judged by
  std::vector<Vec2> removed;  // the input polyline that is gone (a loop: closed)
  std::vector<Vec2> added;    // the polyline that replaces it (empty for an island)
};

struct HealResult {
  std::vector<HealChange> changes;
  int count(HealKind kind) const;
  // The worst change of a kind (the shortest merge, sharpest spike, narrowest inlet, smallest
  // island); null when there is none.
  const HealChange* worst(HealKind kind) const;
};

// Heals `curves` in place. Closed curves (first and last point within the join tolerance) take every
// rule; open curves (parts of a loop of several curves) only merges and spikes between their end
// points, which stay. Constraints and fixed-point curves are left as they are.
HealResult heal_curves(std::vector<RawCurve>& curves, const HealOptions& options = {});

}  // namespace pdmesh
