// CurveScan: squared distances from a point to all of the small curves' segments, kWidth lanes at a
// time (GCC vector extensions; one clone per instruction set, chosen when the program starts), then
// the exact distance for the segments within a margin of each curve's least. The margin covers the
// rounding of both formulas, so the exact rule (least distance, then lowest index) sees every segment
// it could choose.
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

// For each of `curves` consecutive curves (lanes[c] lanes each, a multiple of kWidth): the squared
// distance from (px, py) to each lane's segment into d2, and per lane position the least of the
// curve's (least[kWidth c + k]: the least of its lanes k, k + W, ...). The same operations in every
// clone; they differ only in the vector registers used.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
__attribute__((target_clones("avx512f", "avx2", "default")))
#endif
void squared_distances(double px, double py, const double* ax, const double* ay, const double* dx, const double* dy,
                       const double* inv_len2, const int* lanes, std::size_t curves, double* d2, double* least) {
  const Lanes zero = {};
  const Lanes one = zero + 1.0;
  const Lanes inf = zero + std::numeric_limits<double>::infinity();
  int i = 0;
  for (std::size_t c = 0; c < curves; ++c) {
    Lanes m = inf;
    for (const int end = i + lanes[c]; i < end; i += CurveScan::kWidth) {
      const Lanes rx = px - load(ax + i), ry = py - load(ay + i);
      const Lanes ux = load(dx + i), uy = load(dy + i);
      Lanes t = (rx * ux + ry * uy) * load(inv_len2 + i);
      t = t < zero ? zero : t;
      t = t > one ? one : t;
      const Lanes ex = rx - t * ux, ey = ry - t * uy;
      const Lanes d = ex * ex + ey * ey;
      std::memcpy(d2 + i, &d, sizeof d);
      m = d < m ? d : m;  // NaN (padding) never replaces
    }
    std::memcpy(least + CurveScan::kWidth * c, &m, sizeof m);
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
  }
}

void CurveScan::closest(Vec2 p, std::vector<ClosestHit>& out, ClosestHit* by_square) const {
  alignas(64) double d2[kBatchLanes];
  alignas(64) double least[kBatchLanes];  // kWidth per curve, and a curve has kWidth lanes or more
  const double margin = this->margin(p);
  // The least squared distance, then the lowest index, over every hit measured exactly: each curve's
  // candidates include every segment of it within the margin of its least, so those of the curve
  // nearest p include every segment whose squared distance could tie with the least of all.
  ClosestHit square_best;
  double square_best2 = std::numeric_limits<double>::infinity();
  for (const Batch& b : batches_) {
    const std::size_t f = b.first_lane;
    squared_distances(p.x, p.y, ax_.data() + f, ay_.data() + f, dx_.data() + f, dy_.data() + f, inv_len2_.data() + f,
                      scanned_lanes_.data() + b.first_curve, b.curves, d2, least);
    int first = 0;  // the curve's first lane in d2
    for (std::size_t k = 0; k < b.curves; ++k) {
      const Scanned& s = scanned_[b.first_curve + k];
      const double* lane_least = least + kWidth * k;
      double m = lane_least[0];
      for (int j = 1; j < kWidth; ++j) m = std::min(m, lane_least[j]);
      const double limit = std::sqrt(m) + margin;
      const double limit2 = limit * limit;
      ClosestHit best;
      // Only the lane positions whose least is within the limit hold candidates; within a lane the
      // indices ascend, across lanes the tie goes to the lower index explicitly.
      for (int j = 0; j < kWidth; ++j) {
        if (!(lane_least[j] <= limit2)) continue;
        for (int i = first + j; i < first + s.lanes; i += kWidth) {
          if (!(d2[i] <= limit2)) continue;
          const int id = id_[f + static_cast<std::size_t>(i)];
          const ClosestHit h = detail::closest_on_segment_inline(p, geometry_.segments[static_cast<std::size_t>(id)], id);
          if (best.segment < 0 || h.distance < best.distance || (h.distance == best.distance && id < best.segment)) best = h;
          const double h2 = h.distance * h.distance;
          if (h2 < square_best2 || (h2 == square_best2 && id < square_best.segment)) {
            square_best2 = h2;
            square_best = h;
          }
        }
      }
      out[static_cast<std::size_t>(s.curve)] = best;
      first += s.lanes;
    }
  }
  if (by_square) *by_square = square_best;
}

double CurveScan::margin(Vec2 p) const { return kMargin * std::max({scale_, std::fabs(p.x), std::fabs(p.y)}); }

}  // namespace pdmesh
