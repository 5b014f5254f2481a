// The squared distance from a point to an axis-aligned box: the test every tree search here applies to
// each node and leaf entry it looks at (GeometryTree, FeatureSize).
#pragma once
#include <algorithm>

#include "core/vec2.hpp"

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace pdmesh {

// fmax(v, 0) without the library call: NaN (a NaN query point) gives 0, as fmax does.
inline double positive_part(double v) { return v > 0.0 ? v : 0.0; }

// Squared distance from p to the closed box b (0 inside). The SSE2 form computes both axes at once
// and gives the same bits as the scalar one: maxpd(a, b) is a > b ? a : b lane by lane, so
// maxpd(v, u) is std::max(u, v) and maxpd(w, 0) is positive_part(w), NaN included, and
// dx * dx + dy * dy is one multiply per lane and the same addition.
inline double box_distance2(Vec2 p, const Box& b) {
#if defined(__SSE2__)
  const __m128d q = _mm_set_pd(p.y, p.x);
  const __m128d u = _mm_sub_pd(_mm_loadu_pd(&b.lo.x), q);  // (lo.x - p.x, lo.y - p.y)
  const __m128d v = _mm_sub_pd(q, _mm_loadu_pd(&b.hi.x));  // (p.x - hi.x, p.y - hi.y)
  const __m128d w = _mm_max_pd(_mm_max_pd(v, u), _mm_setzero_pd());
  const __m128d w2 = _mm_mul_pd(w, w);
  return _mm_cvtsd_f64(w2) + _mm_cvtsd_f64(_mm_unpackhi_pd(w2, w2));
#else
  // Both differences are NaN together (NaN p) or both are numbers, so std::max agrees with fmax.
  const double dx = positive_part(std::max(b.lo.x - p.x, p.x - b.hi.x));
  const double dy = positive_part(std::max(b.lo.y - p.y, p.y - b.hi.y));
  return dx * dx + dy * dy;
#endif
}

// Squared distance between the closed boxes a and b (0 where they meet): a lower bound on the squared
// distance from any point of a to any point of b. An empty box (lo 1e300, hi -1e300) is at +inf.
inline double box_box_distance2(const Box& a, const Box& b) {
  const double dx = positive_part(std::max(a.lo.x - b.hi.x, b.lo.x - a.hi.x));
  const double dy = positive_part(std::max(a.lo.y - b.hi.y, b.lo.y - a.hi.y));
  return dx * dx + dy * dy;
}

}  // namespace pdmesh
