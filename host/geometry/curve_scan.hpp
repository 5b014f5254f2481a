// CurveScan: the closest segment of a small curve by one vectorized pass over all its segments (an
// approximate distance filter, then the exact closest_on_segment for the few candidates), the same
// answer bit for bit as the curve's quadtree. Eq. 3.6 asks every curve at every sample point; seen
// from afar a small curve's tree prunes little, and a pass over its segments costs less.
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

#include "geometry/geometry.hpp"
#include "geometry/geometry_tree.hpp"

namespace pdmesh {

class CurveScan {
 public:
  // Curves with more segments than this keep the tree (the pass is linear in the segment count).
  static constexpr int kMaxSegments = 512;

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
  static constexpr int kBatchLanes = 1024;
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
  double scale_ = 0.0;  // coordinate_magnitude of the segments
};

}  // namespace pdmesh
