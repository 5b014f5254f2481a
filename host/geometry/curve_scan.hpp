// CurveScan: the closest segment of a small curve by vectorized passes over its segments, kWidth at
// a time (chunks): the bounding boxes of all chunks, then approximate distances in the chunks whose
// box can hold the least, then the exact closest_on_segment for the few candidates; the same answer
// bit for bit as the curve's quadtree. Eq. 3.6 asks every curve at every sample point; seen from
// afar a small curve's tree prunes little, and flat passes cost less than its branches.
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

#include "geometry/geometry.hpp"
#include "geometry/geometry_tree.hpp"

namespace pdmesh {

class CurveScan {
 public:
  // Curves with more segments than this keep the tree (the box pass is linear in the chunk count).
  // Circles of a few thousand segments (annulus_1m's 2,448 and 1,224) are answered faster by the scan
  // than by their trees, since seen from inside a circle every chord is near (docs/journal/).
  static constexpr int kMaxSegments = 4096;

  // segment_ids[c]: curve c's segment indices, ascending. Keeps a reference to geometry.
  CurveScan(const Geometry& geometry, const std::vector<std::vector<int>>& segment_ids);

  // Whether curve c is scanned (at most kMaxSegments segments, at least one).
  bool covers(int curve) const { return covered_[static_cast<std::size_t>(curve)] != 0; }
  // For every scanned curve c, out[c] = its closest segment to p: the lowest index among those at the
  // least distance, as closest_on_segment measures it (out holds an entry per curve; the others are
  // left as they are). p's coordinates must be finite and at most kMaxMagnitude in size.
  // by_square (optional): the closest segment over the scanned curves by the least squared distance
  // (h.distance * h.distance), then the lowest index.
  void closest(Vec2 p, std::vector<ClosestHit>& out, ClosestHit* by_square = nullptr) const;
  // The filter's margin at p, in distance: candidates lie within it of their curve's least.
  double margin(Vec2 p) const;
  static constexpr double kMaxMagnitude = 1e100;

  // Lanes per vector of the pass, and so the padding of each curve's arrays.
  static constexpr int kWidth = 8;

 private:
  // The scanned curves, their lanes consecutive in curve order; taken kBatchLanes or fewer at a time.
  struct Scanned {
    int curve = 0;
    int lanes = 0;  // a multiple of kWidth
  };
  static constexpr int kBatchLanes = 4096;
  static_assert(kBatchLanes >= (kMaxSegments + kWidth - 1) / kWidth * kWidth,
                "a batch holds the largest scanned curve");
  struct Batch {
    std::size_t first_curve = 0, curves = 0;  // into scanned_
    std::size_t first_lane = 0;
    int lanes = 0;
  };
  const Geometry& geometry_;
  std::vector<std::uint8_t> covered_;  // per curve
  std::vector<Scanned> scanned_;
  std::vector<int> scanned_lanes_;  // scanned_[k].lanes, for the vector pass
  std::vector<Batch> batches_;
  // Per lane: the segment's start, direction b - a and 1 / |b - a|^2 (0 for a point), and its index.
  // Padding lanes hold NaN, which no comparison selects.
  std::vector<double> ax_, ay_, dx_, dy_, inv_len2_;
  std::vector<int> id_;
  // Per chunk (kWidth consecutive lanes of one curve: chunk k holds lanes kWidth k ..): the bounding
  // box of its segments and its first segment's start, and kWidth NaN entries past the last chunk
  // for the vector pass.
  std::vector<double> box_x0_, box_x1_, box_y0_, box_y1_, start_x_, start_y_;
  double scale_ = 0.0;  // coordinate_magnitude of the segments
};

}  // namespace pdmesh
