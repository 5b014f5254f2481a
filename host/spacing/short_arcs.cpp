// short_arc_sources() (short_arcs.hpp).
#include "spacing/short_arcs.hpp"

#include <algorithm>

namespace pdmesh {

std::vector<PointSource> short_arc_sources(const Geometry& geometry, const SpacingField& base, double scale) {
  std::vector<PointSource> sources;
  for (const Curve& c : geometry.curves) {
    if (c.constraint || c.fixed_points) continue;
    const int n = static_cast<int>(c.points.size());
    const bool closed = n > 2 && c.points.front() == c.points.back();
    std::vector<int> crit;
    for (int k = 0; k < n; ++k)
      if (c.critical[static_cast<std::size_t>(k)] && !(closed && k == n - 1)) crit.push_back(k);
    const auto seg_len = [&](int s) {
      const int segs = n - 1;
      if (closed) s = (s % segs + segs) % segs;
      if (s < 0 || s >= segs) return 0.0;
      return dist(c.points[static_cast<std::size_t>(s)], c.points[static_cast<std::size_t>(s + 1)]);
    };
    const std::size_t arcs = closed ? crit.size() : (crit.empty() ? 0 : crit.size() - 1);
    for (std::size_t k = 0; k < arcs && crit.size() >= 2; ++k) {
      const int a = crit[k];
      const int b = k + 1 < crit.size() ? crit[k + 1] : crit[0];
      double arc = c.arc[static_cast<std::size_t>(b)] - c.arc[static_cast<std::size_t>(a)];
      if (b <= a) arc += c.length();  // the arc through a closed curve's first point
      const Vec2 pa = c.points[static_cast<std::size_t>(a)], pb = c.points[static_cast<std::size_t>(b)];
      const double ref = std::max({seg_len(a - 1), seg_len(b), base.at(pa), base.at(pb), base.at(0.5 * (pa + pb))});
      if (!(arc * kShortArcRatio < scale * ref)) continue;
      sources.push_back({pa, arc});
      sources.push_back({pb, arc});
    }
  }
  return sources;
}

}  // namespace pdmesh
