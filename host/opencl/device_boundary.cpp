// Host side of the device's boundary re-snapping; see device_boundary.hpp and kernels/boundary.cl.
#include "opencl/device_boundary.hpp"

#include <algorithm>
#include <cmath>

#include "core/errors.hpp"

namespace pdmesh::ocl {

template <typename Real>
void DeviceBoundary<Real>::upload_curves() {
  Context& ctx = ctx_;
  std::vector<std::int32_t> first{0};
  std::vector<Real> pts, arc;
  for (const Curve& curve : geometry_.curves) {
    for (std::size_t k = 0; k < curve.points.size(); ++k) {
      pts.push_back(static_cast<Real>(curve.points[k].x));
      pts.push_back(static_cast<Real>(curve.points[k].y));
      arc.push_back(static_cast<Real>(curve.arc[k]));
    }
    first.push_back(static_cast<std::int32_t>(arc.size()));
  }
  // Never empty buffers (a geometry has curves; a zero-size clCreateBuffer would fail).
  pts.resize(std::max<std::size_t>(pts.size(), 2));
  arc.resize(std::max<std::size_t>(arc.size(), 1));
  curve_pt_ = Buffer<std::int32_t>(ctx, "curve_first_point", first.size());
  pts_ = Buffer<Real>(ctx, "curve_points", pts.size());
  pt_arc_ = Buffer<Real>(ctx, "curve_point_arc", arc.size());
  std::vector<Real> segs;
  segment_scale_ = 0.0;
  for (const Segment& s : geometry_.segments) {
    for (double v : {s.a.x, s.a.y, s.b.x, s.b.y}) {
      segs.push_back(static_cast<Real>(v));
      segment_scale_ = std::max(segment_scale_, std::fabs(v));
    }
  }
  segs.resize(std::max<std::size_t>(segs.size(), 4));
  segs_ = Buffer<Real>(ctx, "boundary_segments", segs.size());
  segs_.upload(ctx.queue(), segs);
  curve_pt_.upload(ctx.queue(), first);
  pts_.upload(ctx.queue(), pts);
  pt_arc_.upload(ctx.queue(), arc);
}

template <typename Real>
const std::vector<std::int32_t>& DeviceBoundary<Real>::upload_topology(const NodeSet& nodes,
                                                                       const std::vector<std::vector<double>>& arcs) {
  std::vector<std::int32_t> slot(nodes.size(), -1);
  slot_nodes_.clear();
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    if (nodes.kind[i] != NodeKind::Boundary) continue;
    slot[i] = static_cast<std::int32_t>(slot_nodes_.size());
    slot_nodes_.push_back(static_cast<std::int32_t>(i));
  }
  const std::size_t m = slot_nodes_.size();
  std::vector<std::int32_t> curve(m, -1), pos(m, -1);
  std::vector<Real> flat;
  for (std::size_t c = 0; c < nodes.curve_nodes.size(); ++c) {
    const std::vector<int>& list = nodes.curve_nodes[c];
    if (arcs.at(c).size() != list.size())
      throw SimulationError(fmt::format("curve {} has {} nodes but {} arc positions", c, list.size(), arcs[c].size()));
    for (std::size_t k = 0; k < list.size(); ++k) {
      const auto node = static_cast<std::size_t>(list[k]);
      // Boundary nodes have a neighbour entry on both sides (lists start and end with Fixed nodes).
      if (nodes.kind[node] == NodeKind::Boundary && k > 0 && k + 1 < list.size()) {
        const auto s = static_cast<std::size_t>(slot[node]);
        curve[s] = static_cast<std::int32_t>(c);
        pos[s] = static_cast<std::int32_t>(flat.size());
      }
      flat.push_back(static_cast<Real>(arcs[c][k]));
    }
  }
  for (std::size_t s = 0; s < m; ++s)
    if (pos[s] < 0)
      throw SimulationError(fmt::format("boundary node {} is not inside its curve's node list", slot_nodes_[s]));
  arc_entries_ = flat.size();
  flat.resize(std::max<std::size_t>(flat.size(), 1));
  const std::size_t slots = std::max<std::size_t>(m, 1);
  ensure_size(ctx_, slot_node_, "boundary_slot_node", slots);
  ensure_size(ctx_, slot_curve_, "boundary_slot_curve", slots);
  ensure_size(ctx_, slot_pos_, "boundary_slot_pos", slots);
  ensure_size(ctx_, arcs_[0], "boundary_arcs", flat.size());
  ensure_size(ctx_, arcs_[1], "boundary_arcs", flat.size());
  ensure_size(ctx_, partials_, "boundary_partials", std::max<std::size_t>(partial_count(1), 1));
  if (m > 0) {
    slot_node_.upload(ctx_.queue(), slot_nodes_);
    slot_curve_.upload(ctx_.queue(), curve);
    slot_pos_.upload(ctx_.queue(), pos);
  }
  arcs_[0].upload(ctx_.queue(), flat);
  arcs_[1].upload(ctx_.queue(), flat);
  return slot_nodes_;
}

template <typename Real>
BoundarySnapResult DeviceBoundary<Real>::sum(const std::vector<Real>& partials, std::size_t count) {
  BoundarySnapResult r;
  for (std::size_t g = 0; g + kBoundaryPartials <= count; g += kBoundaryPartials) {
    r.clamped += static_cast<std::size_t>(partials[g]);
    r.non_finite += static_cast<std::size_t>(partials[g + 1]);
    r.skin_use = std::max(r.skin_use, static_cast<double>(partials[g + 2]));
  }
  return r;
}

template <typename Real>
void DeviceBoundary<Real>::read_arcs(int which, std::vector<Real>& flat, bool blocking) {
  arcs_[which].download(ctx_.queue(), flat, arc_entries_, blocking);
}

template <typename Real>
std::vector<std::vector<double>> DeviceBoundary<Real>::download_arcs(int which, const NodeSet& nodes) {
  std::vector<Real> flat;
  read_arcs(which, flat, true);
  return unflatten(flat, nodes);
}

template <typename Real>
std::vector<std::vector<double>> DeviceBoundary<Real>::unflatten(const std::vector<Real>& flat, const NodeSet& nodes) {
  std::vector<std::vector<double>> arcs(nodes.curve_nodes.size());
  std::size_t at = 0;
  for (std::size_t c = 0; c < arcs.size(); ++c)
    for (std::size_t k = 0; k < nodes.curve_nodes[c].size(); ++k) arcs[c].push_back(static_cast<double>(flat.at(at++)));
  return arcs;
}

template <typename Real>
std::size_t DeviceBoundary<Real>::bytes() const {
  return curve_pt_.bytes() + slot_node_.bytes() + slot_curve_.bytes() + slot_pos_.bytes() + pts_.bytes() +
         pt_arc_.bytes() + arcs_[0].bytes() + arcs_[1].bytes() + partials_.bytes() + segs_.bytes();
}

template class DeviceBoundary<float>;
template class DeviceBoundary<double>;

}  // namespace pdmesh::ocl
