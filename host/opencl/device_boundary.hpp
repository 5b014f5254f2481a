// Boundary re-snapping on the device (kernels/boundary.cl, boundary_snap): the curves' polylines are
// uploaded once, the boundary nodes' slots (curve, entry in the curve lists) and the arc positions
// whenever the curve lists change; each iteration one launch re-snaps every boundary node exactly as
// BoundaryHandler::move_boundary_nodes does on the host. The arc positions are double-buffered (the
// Jacobi rule reads the old ones); the host reads them back only when it needs the boundary state
// (a snap of an escaped interior node, population events, the saved and final states).
#pragma once
#include <cstdint>
#include <vector>

#include "geometry/geometry.hpp"
#include "nodes/node_set.hpp"
#include "opencl/step_program.hpp"

namespace pdmesh::ocl {

// Sums of boundary_snap's partials over its groups, in group order.
struct BoundarySnapResult {
  std::size_t clamped = 0;     // moves cut short at the allowed arc range (BoundaryCounts::clamped)
  std::size_t non_finite = 0;  // targets that were not finite (nothing written for them)
  double skin_use = 0.0;       // the largest skin use of a re-snapped node
};

template <typename Real>
class DeviceBoundary {
 public:
  // Allocates nothing yet (a run checks the device's memory first).
  DeviceBoundary(Context& ctx, const Geometry& geometry) : ctx_(ctx), geometry_(geometry) {}
  // Uploads the curves' points and cumulative arc lengths (blocking; once, before upload_topology).
  void upload_curves();

  // The slots of the Boundary nodes in index order (device_step's bslot order) and the arc positions
  // (parallel to nodes.curve_nodes), into both arc buffers. Returns the slots' nodes.
  const std::vector<std::int32_t>& upload_topology(const NodeSet& nodes, const std::vector<std::vector<double>>& arcs);

  // Enqueues boundary_snap: moves from brec (x, y, dx, dy per slot), old arcs in buffer `cur`, new
  // ones into 1 - cur; writes xy (positions, x and y interleaved), q, tx, ty and node_leaf of the
  // boundary nodes, unless step_counters[kCounterNonFinite] != 0 (device_step's flag for a move that
  // is not finite). `bg` sets the background field's arguments
  // (DeviceRun::bg_args). With `rule` (DeviceWindow::rule_args, given the ArgSetter) the launch is
  // boundary_snap_rule, which also ends the iteration (kernels/boundary.cl). No-op without boundary
  // nodes; returns whether it launched.
  template <typename BgArgs, typename RuleArgs = void(ArgSetter&)>
  bool enqueue(StepProgram& program, int cur, Buffer<Real>& brec, Buffer<Real>& xy, Buffer<Real>& q, Buffer<Real>& tx,
               Buffer<Real>& ty, Buffer<std::int32_t>& node_leaf, Buffer<Real>& xy_build, Buffer<Real>& q_build,
               Buffer<std::uint8_t>& skin_class, double cutoff, double skin_cutoff, Buffer<std::int32_t>& step_counters,
               BgArgs&& bg, RuleArgs* rule = nullptr) {
    if (slots() == 0) return false;
    cl::Kernel& kernel = rule ? program.boundary_snap_rule : program.boundary_snap;
    const char* name = rule ? "boundary_snap_rule" : "boundary_snap";
    ArgSetter a(kernel, name);
    a(static_cast<cl_int>(slots()))(slot_node_)(slot_curve_)(slot_pos_)(curve_pt_)(pts_)(pt_arc_)(arcs_[cur])(
        arcs_[1 - cur])(brec)(xy)(q)(tx)(ty)(node_leaf)(xy_build)(q_build)(skin_class)(static_cast<Real>(cutoff))(
        static_cast<Real>(skin_cutoff))(step_counters)(partials_);
    bg(a);
    if (rule) (*rule)(a);
    launch(ctx_.queue(), kernel, name, slots(), program.work_group);
    return true;
  }
  // Every boundary segment as (ax, ay, bx, by), Geometry::segments order, for the clearance refresh
  // (kernels/clearance.cl), uploaded by upload_curves; segment_scale: the largest |coordinate| of a
  // segment end.
  Buffer<Real>& segments() { return segs_; }
  int segment_count() const { return static_cast<int>(geometry_.segments.size()); }
  double segment_scale() const { return segment_scale_; }
  // The partials buffer and how many entries the last topology's launch writes (for the caller's reads).
  Buffer<Real>& partials() { return partials_; }
  std::size_t partial_count(std::size_t work_group) const {
    return kBoundaryPartials * ((slots() + work_group - 1) / work_group);
  }
  static BoundarySnapResult sum(const std::vector<Real>& partials, std::size_t count);
  // Arc buffer `which` back into the per-curve layout of nodes.curve_nodes (blocking read), or in two
  // steps: enqueue the read into `flat` (blocking or not), then, after a wait, unflatten it.
  std::vector<std::vector<double>> download_arcs(int which, const NodeSet& nodes);
  void read_arcs(int which, std::vector<Real>& flat, bool blocking);
  static std::vector<std::vector<double>> unflatten(const std::vector<Real>& flat, const NodeSet& nodes);

  std::size_t slots() const { return slot_nodes_.size(); }
  std::size_t arc_entries() const { return arc_entries_; }  // entries of all curve lists
  std::size_t bytes() const;

 private:
  Context& ctx_;
  const Geometry& geometry_;
  Buffer<std::int32_t> curve_pt_, slot_node_, slot_curve_, slot_pos_;
  Buffer<Real> pts_, pt_arc_, arcs_[2], partials_, segs_;
  double segment_scale_ = 0.0;
  std::vector<std::int32_t> slot_nodes_;
  std::size_t arc_entries_ = 0;
};

}  // namespace pdmesh::ocl
