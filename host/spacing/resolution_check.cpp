// Coordinates that double precision cannot resolve at the segment and spacing scale; see
// resolution_check.hpp.
#include "spacing/resolution_check.hpp"

#include <cfloat>
#include <cmath>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "core/errors.hpp"

namespace pdmesh {

void check_coordinate_resolution(const Geometry& geometry, const SpacingField& spacing) {
  double largest = 0.0;
  std::string largest_where;
  for (const Curve& c : geometry.curves)
    for (std::size_t k = 0; k < c.points.size(); ++k) {
      const double m = std::fmax(std::fabs(c.points[k].x), std::fabs(c.points[k].y));
      if (m > largest) {
        largest = m;
        largest_where = fmt::format("{}:{} (curve '{}', point {})", c.file, c.line + static_cast<int>(k), c.name, k);
      }
    }
  const double quantum = largest * DBL_EPSILON;  // 2^-52
  const double needed = kResolutionQuanta * quantum;
  if (!(needed > 0.0)) return;
  const auto refuse = [&](const std::string& what, double value) {
    throw LimitError(fmt::format(
        "{} is {:.6g}, but the coordinates reach {:.6g} at {}, where doubles are {:.3g} apart; the simulation "
        "needs segments and spacings of at least {:g} times that ({:.3g}): move the geometry nearer the origin "
        "(subtract a common offset) or use a coarser spacing",
        what, value, largest, largest_where, quantum, kResolutionQuanta, needed));
  };
  for (const Segment& s : geometry.segments)
    if (s.length < needed) {
      const Curve& c = geometry.curves[static_cast<std::size_t>(s.curve)];
      refuse(fmt::format("{}:{}: the segment {} of curve '{}' from ({}, {}) to ({}, {})", c.file, c.line + s.index,
                         s.index, c.name, s.a.x, s.a.y, s.b.x, s.b.y),
             s.length);
    }
  // The spacing where nodes are placed first: at the curve points (where the boundary field takes
  // its extremes) and, for expression fields, the middle of the domain.
  const Vec2 centre{0.5 * (geometry.extents.lo.x + geometry.extents.hi.x),
                    0.5 * (geometry.extents.lo.y + geometry.extents.hi.y)};
  // One batch (a field backed by an interpreter is not called per point).
  std::vector<Vec2> points{centre};
  for (const Curve& c : geometry.curves) points.insert(points.end(), c.points.begin(), c.points.end());
  std::vector<double> q;
  spacing.at_many(points, q);
  double smallest = q[0];
  Vec2 where = centre;
  for (std::size_t i = 1; i < points.size(); ++i)
    if (q[i] < smallest) {
      smallest = q[i];
      where = points[i];
    }
  // A denormal spacing (an underflow, e.g. 1e-310) is too small at any coordinate: say so, not that
  // the coordinates are too large.
  if (smallest > 0.0 && smallest < DBL_MIN) {
    throw LimitError(
        fmt::format("the spacing at ({}, {}) is {:.6g}, below the smallest normal double ({:g}): a value "
                    "that small underflows; the simulation needs spacings of at least {:.3g} here",
                    where.x, where.y, smallest, DBL_MIN, needed));
  }
  if (smallest < needed) refuse(fmt::format("the spacing at ({}, {})", where.x, where.y), smallest);
}

}  // namespace pdmesh
