// Clearance-budget refresh on the device (host/sim/boundary_handling.cpp, BoundaryHandler::
// clearance_from and the refresh rule of move_interior_node): when an interior node's budget runs out,
// device_step computes a lower bound D of the distance from its new position p to the boundary. When
// the node was known inside (budget > 0) and the move's cost is below D, the old position lies in the
// open disc of radius D around p, which holds no boundary point: the whole disc, p and the move are
// inside, so the host's exact test would accept the move; the node gets the budget D without leaving
// the device. Only nodes whose move is comparable to their distance to the boundary go to the host.
// In double D is the host's clearance_from(p) bit for bit: the exact minimum over every segment of
// closest_on_segment's distance (the same operations, FP_CONTRACT OFF; sqrt is monotonic, so the
// minimum of the squared distances gives the same root), and the same margins. In float D is a
// conservative bound with margins for float's rounding of the segments and of the search.
#pragma OPENCL FP_CONTRACT OFF

#if PDMESH_DOUBLE
#define CLEARANCE_EPS DBL_EPSILON
#else
#define CLEARANCE_EPS FLT_EPSILON
#endif

// The point of segment a -> b (ab = b - a) at parameter t, exactly a at 0 and b at 1 (closest_on_segment's
// rule, and closest_on_curve_range's in boundary.cl), and its squared distance from p.
REAL segment_point(const REAL ax, const REAL ay, const REAL bx, const REAL by, const REAL abx, const REAL aby,
                   const REAL t, const REAL px, const REAL py, REAL2* on) {
  const REAL qx = t == (REAL)0 ? ax : t == (REAL)1 ? bx : ax + t * abx;
  const REAL qy = t == (REAL)0 ? ay : t == (REAL)1 ? by : ay + t * aby;
  *on = (REAL2)(qx, qy);
  const REAL ex = px - qx, ey = py - qy;
  return ex * ex + ey * ey;
}

// The search's margin at p (scale: |px| + |py| + seg_scale): a segment whose bounding box lies further
// than best + margin cannot beat the best computed distance: both are within a few ulps of the scale
// of the true ones.
REAL clearance_margin(const REAL scale) { return (REAL)64 * CLEARANCE_EPS * scale; }

// The smallest squared distance closest_on_segment gives from (px, py) to the segments first,
// first + stride, ... below n_segs (INFINITY for none), skipping the segments whose bounding box lies
// beyond the best so far plus the margin. A skipped segment's distance exceeds the best of the same
// walk, so the result is the minimum over the walked segments whatever was skipped; and the minimum
// of several walks (clearance_group_nearest2) is the minimum over all of them.
REAL clearance_nearest2(const REAL px, const REAL py, __global const REAL* segs, const int first, const int stride,
                        const int n_segs, const REAL margin) {
  REAL best2 = INFINITY, limit2 = INFINITY;
  for (int s = first; s < n_segs; s += stride) {
    const REAL ax = segs[4 * s], ay = segs[4 * s + 1], bx = segs[4 * s + 2], by = segs[4 * s + 3];
    const REAL gx = px < fmin(ax, bx) ? fmin(ax, bx) - px : (px > fmax(ax, bx) ? px - fmax(ax, bx) : (REAL)0);
    const REAL gy = py < fmin(ay, by) ? fmin(ay, by) - py : (py > fmax(ay, by) ? py - fmax(ay, by) : (REAL)0);
    if (gx * gx + gy * gy > limit2) continue;
    // closest_on_segment (host/geometry/geometry_tree.cpp): t = dot(p - a, ab) / |ab|^2 clamped to
    // [0, 1], the point a, b or a + t ab, its squared distance.
    const REAL abx = bx - ax, aby = by - ay;
    const REAL len2 = abx * abx + aby * aby;
    REAL t = len2 > (REAL)0 ? ((px - ax) * abx + (py - ay) * aby) / len2 : (REAL)0;
    t = t < (REAL)0 ? (REAL)0 : ((REAL)1 < t ? (REAL)1 : t);
    REAL2 q;
    const REAL d2 = segment_point(ax, ay, bx, by, abx, aby, t, px, py, &q);
    if (d2 < best2) {
      best2 = d2;
      const REAL lim = sqrt(best2) + margin;
      limit2 = lim * lim;
    }
  }
  return best2;
}

// The bound from the smallest squared distance best2 at (px, py) (finite): 0 where the host must
// decide (no segments, or p within 1e-12 of the scale of a segment, where the host's
// closest_on_segment may snap the distance to 0 by its exact on-segment predicate).
REAL clearance_from_nearest2(const REAL best2, const REAL px, const REAL py, const REAL scale) {
  if (!(best2 < INFINITY)) return (REAL)0;
  const REAL best = sqrt(best2);
  if (best <= REAL_C(1e-12) * scale) return (REAL)0;
#if PDMESH_DOUBLE
  // BoundaryHandler::clearance_from's margins, the same expression.
  const REAL d = best - (REAL)16 * DBL_EPSILON * (fabs(px) + fabs(py) + best);
  return d > (REAL)0 ? d * ((REAL)1 - (REAL)1e-6) : (REAL)0;
#else
  // Float: the segments are rounded to float (up to eps seg_scale) and the search rounds at the scale.
  const REAL d = best - (REAL)64 * FLT_EPSILON * (scale + best);
  return d > (REAL)0 ? d * ((REAL)1 - (REAL)64 * FLT_EPSILON) : (REAL)0;
#endif
}

// segs: (ax, ay, bx, by) per boundary segment in Geometry::segments order; seg_scale: the largest
// |coordinate| of any segment end (DeviceBoundary::segment_scale). One work-item walks every segment.
// Returns 0 where the host must decide: no segments, a non-finite p, or p within 1e-12 of the scale
// of a segment.
REAL clearance_bound(const REAL px, const REAL py, __global const REAL* segs, const int n_segs, const REAL seg_scale) {
  if (!(isfinite(px) && isfinite(py))) return (REAL)0;
  const REAL scale = fabs(px) + fabs(py) + seg_scale;
  return clearance_from_nearest2(clearance_nearest2(px, py, segs, 0, 1, n_segs, clearance_margin(scale)), px, py,
                                 scale);
}

// clearance_bound by a whole work-group (every work-item calls it with the same point; uniform
// control flow): work-item l walks segments l, l + WG_SIZE, ..., and the group takes the least of
// their minima (lane_best: WG_SIZE entries of local memory, free again on return). The minimum of
// the same squared distances in another order: bit for bit clearance_bound's result. The values are
// +0.0, positive or INFINITY (sums of squares that compared below INFINITY), so the order of `<`
// cannot matter.
REAL clearance_bound_group(const REAL px, const REAL py, __global const REAL* segs, const int n_segs,
                           const REAL seg_scale, __local REAL* lane_best) {
  // A non-finite p (0: the host decides) passes the barriers too: a caller may rely on them
  // (refresh_budgets rewrites its list entry after every work-item read it).
  const int finite = isfinite(px) && isfinite(py);
  const int l = get_local_id(0);
  const REAL scale = fabs(px) + fabs(py) + seg_scale;
  lane_best[l] = finite ? clearance_nearest2(px, py, segs, l, WG_SIZE, n_segs, clearance_margin(scale)) : INFINITY;
  for (int width = WG_SIZE / 2; width > 0; width /= 2) {
    barrier(CLK_LOCAL_MEM_FENCE);
    if (l < width) {
      const REAL a = lane_best[l], b = lane_best[l + width];
      lane_best[l] = b < a ? b : a;
    }
  }
  barrier(CLK_LOCAL_MEM_FENCE);
  const REAL best2 = lane_best[0];
  barrier(CLK_LOCAL_MEM_FENCE);  // read by every work-item before the next call writes
  return finite ? clearance_from_nearest2(best2, px, py, scale) : (REAL)0;
}

// BoundaryHandler::move_cost with this precision's epsilon: an upper bound of what a move by (ex, ey)
// ending at (px, py) uses of a budget b.
REAL clearance_move_cost(const REAL ex, const REAL ey, const REAL px, const REAL py, const REAL b) {
  return sqrt(ex * ex + ey * ey) * ((REAL)1 + (REAL)64 * CLEARANCE_EPS) +
         (REAL)8 * CLEARANCE_EPS * (fabs(px) + fabs(py) + b);
}

// The refresh rule for a node known inside (its budget was > 0) whose move (ex, ey) to (px, py) cost
// more than its budget, given the bound d at (px, py): the new budget (> 0) when the move is accepted
// on the device, else 0 (the host's exact test decides).
REAL clearance_accept(const REAL ex, const REAL ey, const REAL px, const REAL py, const REAL d) {
  return d > (REAL)0 && clearance_move_cost(ex, ey, px, py, d) < d ? d : (REAL)0;
}

REAL clearance_refresh(const REAL ex, const REAL ey, const REAL px, const REAL py, __global const REAL* segs,
                       const int n_segs, const REAL seg_scale) {
  return clearance_accept(ex, ey, px, py, clearance_bound(px, py, segs, n_segs, seg_scale));
}

// For tests (tests/test_device_clearance.cpp): the refresh of m moves from (x, y) by (dx, dy), and the
// bound at the new positions.
__kernel __attribute__((reqd_work_group_size(WG_SIZE, 1, 1))) void clearance_points(
    const int m, __global const REAL* x, __global const REAL* y, __global const REAL* dx, __global const REAL* dy,
    __global const REAL* segs, const int n_segs, const REAL seg_scale, __global REAL* bound, __global REAL* refreshed) {
  const int k = get_global_id(0);
  if (k >= m) return;
  const REAL px = x[k] + dx[k], py = y[k] + dy[k];
  bound[k] = clearance_bound(px, py, segs, n_segs, seg_scale);
  refreshed[k] = clearance_refresh(px - x[k], py - y[k], px, py, segs, n_segs, seg_scale);
}

// The same by clearance_bound_group: one work-group per point (the launch covers m groups).
__kernel __attribute__((reqd_work_group_size(WG_SIZE, 1, 1))) void clearance_points_group(
    const int m, __global const REAL* x, __global const REAL* y, __global const REAL* dx, __global const REAL* dy,
    __global const REAL* segs, const int n_segs, const REAL seg_scale, __global REAL* bound, __global REAL* refreshed) {
  __local REAL lane_best[WG_SIZE];
  const int k = get_group_id(0);
  if (k >= m) return;  // uniform
  const REAL px = x[k] + dx[k], py = y[k] + dy[k];
  const REAL d = clearance_bound_group(px, py, segs, n_segs, seg_scale, lane_best);
  if (get_local_id(0) == 0) {
    bound[k] = d;
    refreshed[k] = clearance_accept(px - x[k], py - y[k], px, py, d);
  }
}
