// CurveScan: squared distances from a point to the small curves' segments, kWidth lanes at a time
// (GCC vector extensions; one clone per instruction set, chosen when the program starts) in the
// chunks whose bounding box can hold the least, then the exact distance for the segments within a
// margin of each curve's least. The margin covers the rounding of both formulas and of the box
// bound, so the exact rule (least distance, then lowest index) sees every segment it could choose.
#include "geometry/curve_scan.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#include "geometry/closest_on_segment.hpp"

// The vector type is passed only between inlined functions of one clone; GCC's note that a 64-byte
// vector would be passed differently without AVX-512 does not apply.
#pragma GCC diagnostic ignored "-Wpsabi"

namespace pdmesh {

namespace {

using Lanes = double __attribute__((vector_size(CurveScan::kWidth * sizeof(double))));

// Inlined into each clone (so no vector crosses a call in the default instruction set's ABI).
inline __attribute__((always_inline)) Lanes load(const double* p) {
  Lanes v;
  std::memcpy(&v, p, sizeof v);
  return v;
}

inline __attribute__((always_inline)) double least_lane(const Lanes& v) {
  double m = v[0];
  for (int j = 1; j < CurveScan::kWidth; ++j) m = v[j] < m ? v[j] : m;
  return m;
}

// The squared distance from (px, py) to each segment of the chunk at lane i (infinity for none: a
// padding lane's NaN never passes a comparison).
inline __attribute__((always_inline)) Lanes chunk_distances(double px, double py, const double* ax, const double* ay,
                                                            const double* dx, const double* dy, const double* inv_len2,
                                                            int i) {
  const Lanes zero = {};
  const Lanes one = zero + 1.0;
  const Lanes rx = px - load(ax + i), ry = py - load(ay + i);
  const Lanes ux = load(dx + i), uy = load(dy + i);
  Lanes t = (rx * ux + ry * uy) * load(inv_len2 + i);
  t = t < zero ? zero : t;
  t = t > one ? one : t;
  const Lanes ex = rx - t * ux, ey = ry - t * uy;
  return ex * ex + ey * ey;
}

// One batch of consecutive curves (lanes[c] lanes each, a multiple of kWidth; `chunks` chunks of
// kWidth lanes in all). First, for every chunk, the squared distance from (px, py) to its bounding
// box (a lower bound for its segments) and to its first segment's start (an upper bound for the
// least of them); then per curve the least upper bound u, and the chunks whose box lies within
// sqrt(u) + 2 margin: no segment of a chunk beyond that can come within the caller's margin of the
// curve's least (the box bound and either distance formula round far below the margin), so the
// least and every candidate are those of a pass over all segments. Each step runs over all curves
// before the next, so that the curves' chains of dependent operations overlap. Out: the measured
// chunks' squared distances (kWidth each, d2), their indices in the batch (measured), each curve's
// end in them (measured_end[c]) and its least squared distance (least[c]). The same operations in
// every clone; they differ only in the vector registers used.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
__attribute__((target_clones("avx512f", "avx2", "default")))
#endif
void scan_batch(double px, double py, double margin, const double* ax, const double* ay, const double* dx,
                const double* dy, const double* inv_len2, const double* box_x0, const double* box_x1,
                const double* box_y0, const double* box_y1, const double* start_x, const double* start_y,
                const int* lanes, std::size_t curves, int chunks, double* box2, double* upper2, double* bound2,
                double* d2, int* measured, int* measured_end, double* least) {
  const Lanes zero = {};
  const Lanes inf = zero + std::numeric_limits<double>::infinity();
  for (int k = 0; k < chunks; k += CurveScan::kWidth) {
    Lanes gx = load(box_x0 + k) - px, gy = load(box_y0 + k) - py;
    const Lanes hx = px - load(box_x1 + k), hy = py - load(box_y1 + k);
    gx = gx > hx ? gx : hx;
    gy = gy > hy ? gy : hy;
    gx = gx > zero ? gx : zero;
    gy = gy > zero ? gy : zero;
    const Lanes b = gx * gx + gy * gy;
    std::memcpy(box2 + k, &b, sizeof b);
    const Lanes sx = px - load(start_x + k), sy = py - load(start_y + k);
    const Lanes u = sx * sx + sy * sy;
    std::memcpy(upper2 + k, &u, sizeof u);
  }
  for (std::size_t c = 0, first = 0; c < curves; ++c) {
    const std::size_t end = first + static_cast<std::size_t>(lanes[c] / CurveScan::kWidth);
    double u = upper2[first];
    for (std::size_t k = first + 1; k < end; ++k) u = upper2[k] < u ? upper2[k] : u;
    const double bound = std::sqrt(u) + 2.0 * margin;
    bound2[c] = bound * bound;
    first = end;
  }
  int n = 0;  // chunks measured
  for (std::size_t c = 0, first = 0; c < curves; ++c) {
    const std::size_t end = first + static_cast<std::size_t>(lanes[c] / CurveScan::kWidth);
    Lanes m = inf;
    for (std::size_t k = first; k < end; ++k) {
      if (!(box2[k] <= bound2[c])) continue;
      const Lanes d = chunk_distances(px, py, ax, ay, dx, dy, inv_len2, static_cast<int>(CurveScan::kWidth * k));
      std::memcpy(d2 + CurveScan::kWidth * n, &d, sizeof d);
      measured[n++] = static_cast<int>(k);
      m = d < m ? d : m;  // NaN (padding) never replaces
    }
    least[c] = least_lane(m);
    measured_end[c] = n;
    first = end;
  }
}

// The margin of the filter, in distance, per unit of coordinate magnitude. Either formula's distance
// is within ~50 ulps of the magnitude of the true one, and closest_on_segment snaps distances up to
// 1e-12 of it to 0 (a point on the segment): 4e-12 is far above both together.
constexpr double kMargin = 4e-12;

}  // namespace

CurveScan::CurveScan(const Geometry& geometry, const std::vector<std::vector<int>>& segment_ids)
    : geometry_(geometry), covered_(segment_ids.size(), 0), scale_(coordinate_magnitude(geometry.segments)) {
  const auto& segs = geometry.segments;
  if (!(scale_ <= kMaxMagnitude)) return;  // nothing scanned: the trees answer
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (std::size_t c = 0; c < segment_ids.size(); ++c) {
    const std::vector<int>& ids = segment_ids[c];
    if (ids.empty() || ids.size() > static_cast<std::size_t>(kMaxSegments)) continue;
    // 1 / |b - a|^2 must be finite for every segment that is not a point (a subnormal length squared
    // would overflow it): otherwise the tree answers for this curve.
    bool ok = true;
    for (const int id : ids) {
      const Segment& s = segs[static_cast<std::size_t>(id)];
      const double len2 = norm2(s.b - s.a);
      ok = ok && (len2 == 0.0 || (len2 >= std::numeric_limits<double>::min() && std::isfinite(1.0 / len2)));
    }
    if (!ok) continue;
    covered_[c] = 1;
    const int lanes = static_cast<int>((ids.size() + kWidth - 1) / kWidth * kWidth);
    if (batches_.empty() || batches_.back().lanes + lanes > kBatchLanes)
      batches_.push_back(Batch{scanned_.size(), 0, ax_.size(), 0});
    ++batches_.back().curves;
    batches_.back().lanes += lanes;
    scanned_.push_back(Scanned{static_cast<int>(c), lanes});
    scanned_lanes_.push_back(lanes);
    for (int k = 0; k < lanes; ++k) {
      if (static_cast<std::size_t>(k) < ids.size()) {
        const int id = ids[static_cast<std::size_t>(k)];
        const Segment& s = segs[static_cast<std::size_t>(id)];
        const double len2 = norm2(s.b - s.a);
        ax_.push_back(s.a.x);
        ay_.push_back(s.a.y);
        dx_.push_back(s.b.x - s.a.x);
        dy_.push_back(s.b.y - s.a.y);
        inv_len2_.push_back(len2 > 0.0 ? 1.0 / len2 : 0.0);
        id_.push_back(id);
      } else {
        for (auto* v : {&ax_, &ay_, &dx_, &dy_, &inv_len2_}) v->push_back(nan);
        id_.push_back(-1);
      }
    }
    for (int k = 0; k < lanes; k += kWidth) {
      double x0 = std::numeric_limits<double>::infinity(), y0 = x0, x1 = -x0, y1 = -x0;
      for (int j = k; j < k + kWidth && static_cast<std::size_t>(j) < ids.size(); ++j) {
        const Segment& s = segs[static_cast<std::size_t>(ids[static_cast<std::size_t>(j)])];
        x0 = std::min({x0, s.a.x, s.b.x});
        x1 = std::max({x1, s.a.x, s.b.x});
        y0 = std::min({y0, s.a.y, s.b.y});
        y1 = std::max({y1, s.a.y, s.b.y});
      }
      const Segment& s0 = segs[static_cast<std::size_t>(ids[static_cast<std::size_t>(k)])];
      start_x_.push_back(s0.a.x);
      start_y_.push_back(s0.a.y);
      box_x0_.push_back(x0);
      box_x1_.push_back(x1);
      box_y0_.push_back(y0);
      box_y1_.push_back(y1);
    }
  }
  for (auto* v : {&box_x0_, &box_x1_, &box_y0_, &box_y1_, &start_x_, &start_y_}) v->insert(v->end(), kWidth, nan);
}

void CurveScan::closest(Vec2 p, std::vector<ClosestHit>& out, ClosestHit* by_square) const {
  constexpr int kBatchChunks = kBatchLanes / kWidth;
  alignas(64) double box2[kBatchChunks + kWidth], upper2[kBatchChunks + kWidth];
  alignas(64) double d2[kBatchLanes];
  int measured[kBatchChunks], measured_end[kBatchChunks];  // a curve has one chunk or more
  int candidates[kBatchLanes];                             // one curve's, as lanes of the batch
  double least[kBatchChunks], bound2[kBatchChunks];
  const double margin = this->margin(p);
  // The least squared distance, then the lowest index, over every hit measured exactly: each curve's
  // candidates include every segment of it within the margin of its least, so those of the curve
  // nearest p include every segment whose squared distance could tie with the least of all.
  ClosestHit square_best;
  double square_best2 = std::numeric_limits<double>::infinity();
  for (const Batch& b : batches_) {
    const std::size_t f = b.first_lane, fc = f / kWidth;
    scan_batch(p.x, p.y, margin, ax_.data() + f, ay_.data() + f, dx_.data() + f, dy_.data() + f, inv_len2_.data() + f,
               box_x0_.data() + fc, box_x1_.data() + fc, box_y0_.data() + fc, box_y1_.data() + fc, start_x_.data() + fc,
               start_y_.data() + fc, scanned_lanes_.data() + b.first_curve, b.curves, b.lanes / kWidth, box2, upper2,
               bound2, d2, measured, measured_end, least);
    int begin = 0;  // the curve's first measured chunk
    for (std::size_t k = 0; k < b.curves; ++k) {
      const Scanned& s = scanned_[b.first_curve + k];
      const double limit = std::sqrt(least[k]) + margin;
      const double limit2 = limit * limit;
      ClosestHit best;
      // The candidates first, without a branch per lane (which lanes pass is hard to predict); their
      // order does not matter: ties go to the lower index explicitly.
      int count = 0;
      for (int r = begin; r < measured_end[k]; ++r) {
        const double* d = d2 + kWidth * r;
        const int lane = kWidth * measured[r];
        for (int j = 0; j < kWidth; ++j) {
          candidates[count] = lane + j;
          count += d[j] <= limit2 ? 1 : 0;
        }
      }
      for (int c = 0; c < count; ++c) {
        const int id = id_[f + static_cast<std::size_t>(candidates[c])];
        const ClosestHit h = detail::closest_on_segment_inline(p, geometry_.segments[static_cast<std::size_t>(id)], id);
        if (best.segment < 0 || h.distance < best.distance || (h.distance == best.distance && id < best.segment))
          best = h;
        const double h2 = h.distance * h.distance;
        if (h2 < square_best2 || (h2 == square_best2 && id < square_best.segment)) {
          square_best2 = h2;
          square_best = h;
        }
      }
      out[static_cast<std::size_t>(s.curve)] = best;
      begin = measured_end[k];
    }
  }
  if (by_square) *by_square = square_best;
}

double CurveScan::margin(Vec2 p) const { return kMargin * std::max({scale_, std::fabs(p.x), std::fabs(p.y)}); }

}  // namespace pdmesh
