// Node smoothing of the cleanup in a metric. A node's proposal is the mean over its neighbours b of
// the point at unit metric length from b towards the node, b + (a - b) / L(a, b): where every edge of
// its ball would have length 1 if the others stayed. A boundary node's proposal is projected onto its
// own curve, between its curve neighbours. The step is halved until it is taken or line_search steps
// fail; it is taken when every triangle of the ball stays strictly counter-clockwise (exact
// orient2d), the ball's smallest Q does not drop, no more of its edges than before lie outside the
// window [1/√2, √2], and either that minimum rises or the ball's edges come nearer unit length (the
// sum of ln² L drops). The metric at the new place is the field's. The climb moves the nodes of the
// triangles below a Q up the gradient of their ball's worst Q instead (the same guards, but for a ball
// whose smallest Q is below MetricOpsOptions::repair_below: there a rise of that minimum is enough,
// even when edges leave the window, since near a curved wall whose metric is much finer across it
// than along it no chord can keep every edge in the window, and the guard would freeze the worst
// triangle of the mesh there). A node is tried again only when its ball changed since its last try
// (the editable mesh's dirty marks): with the same ball it would make the same proposal and be
// refused again, so the sweeps end when nothing is left to gain, and the result is the same as
// trying every node every time.
#include <cmath>
#include <limits>

#include "cleanup/metric_ops.hpp"
#include "core/predicates.hpp"
#include "geometry/curve_projection.hpp"

namespace pdmesh::cleanup {
namespace {

// A boundary vertex moves at most this fraction of the arc gap to each curve neighbour per move, so
// neighbours never meet or cross (the isotropic Smoother uses the same).
constexpr double kArcGapFraction = 0.45;
// The climb's probe and step, in metric units.
constexpr double kProbe = 1e-4;
constexpr double kClimbStep = 0.1;
// The least relative gain of a move (rounding aside).
constexpr double kMoveGain = 1e-9;

bool outside_window(double l) { return l < kMetricShort || l > kMetricLong; }

}  // namespace

Vec2 MetricOps::proposal(int a) const {
  Vec2 sum{0.0, 0.0};
  for (int b : ring_) {
    const double l = metric_.length(a, b);
    sum = sum + (m_.p[b] + (1.0 / l) * (m_.p[a] - m_.p[b]));
  }
  return (1.0 / static_cast<double>(ring_.size())) * sum;
}

bool MetricOps::try_position(int a, Vec2 to, double to_arc, double old_min, double old_error, int old_outside,
                             bool repair) {
  const Metric ma = metric_.at(to);
  double new_min = std::numeric_limits<double>::infinity();
  for (int t : fan_) {
    const auto& tv = m_.v[t];
    const int k = EditableMesh::index_of(tv, a);
    const int y = tv[next3(k)], z = tv[prev3(k)];
    if (!(orient2d(to, m_.p[y], m_.p[z]) > 0.0)) return false;
    const Metric my = metric_.at(y), mz = metric_.at(z);
    new_min = std::min(new_min, MetricEvaluator::quality(to, m_.p[y], m_.p[z], ma, my, mz));
    if (new_min < old_min) return false;
  }
  double new_error = 0.0;
  int new_outside = 0;
  for (int b : ring_) {
    const double l = metric_.length(to, ma, m_.p[b], metric_.at(b));
    new_error += std::log(l) * std::log(l);
    new_outside += outside_window(l) ? 1 : 0;
  }
  const bool rises = new_min > old_min + kMoveGain * std::fabs(old_min);
  if (new_outside > old_outside && !(repair && rises)) return false;
  const bool nearer = new_error < old_error * (1.0 - kMoveGain);
  if (!rises && !(nearer && new_min >= old_min)) return false;
  m_.move(a, to, to_arc, fan_);
  return true;
}

Vec2 MetricOps::ascent(int a) const {
  // The worst triangle of a's ball and its Q as a function of a's position.
  int worst = -1;
  double lowest = std::numeric_limits<double>::infinity();
  for (int t : fan_) {
    const double q = m_.quality(t);
    if (q < lowest) {
      lowest = q;
      worst = t;
    }
  }
  const auto& tv = m_.v[worst];
  const int k = EditableMesh::index_of(tv, a);
  const int y = tv[next3(k)], z = tv[prev3(k)];
  const Metric my = metric_.at(y), mz = metric_.at(z);
  const auto q_at = [&](Vec2 x) { return MetricEvaluator::quality(x, m_.p[y], m_.p[z], metric_.at(x), my, mz); };
  // Central differences along the metric's axes at a, in steps of kProbe metric units; the step
  // goes kClimbStep metric units up the gradient.
  const MetricEigen e = eigen(metric_.at(a));
  const Vec2 u1 = (1.0 / std::sqrt(e.lambda1)) * e.v1(), u2 = (1.0 / std::sqrt(e.lambda2)) * e.v2();
  const Vec2 x = m_.p[a];
  const double g1 = q_at(x + kProbe * u1) - q_at(x - kProbe * u1);
  const double g2 = q_at(x + kProbe * u2) - q_at(x - kProbe * u2);
  const double g = std::hypot(g1, g2);
  if (!(g > 0.0)) return {0.0, 0.0};
  return (kClimbStep / g) * (g1 * u1 + g2 * u2);
}

bool MetricOps::move_vertex(int a, bool climb) {
  if (m_.removed(a) || !m_.movable(a)) return false;
  const bool sliding = m_.kind[a] == NodeKind::Boundary;
  if (sliding && m_.curve[a] < 0) return false;
  m_.star(a, fan_);
  m_.ring(a, ring_);
  if (fan_.empty() || ring_.empty()) return false;
  double old_min = std::numeric_limits<double>::infinity(), old_error = 0.0;
  int old_outside = 0;
  for (int t : fan_) old_min = std::min(old_min, m_.quality(t));
  for (int b : ring_) {
    const double l = metric_.length(a, b);
    old_error += std::log(l) * std::log(l);
    old_outside += outside_window(l) ? 1 : 0;
  }
  const bool repair = climb && old_min < options_.repair_below;
  const Vec2 from = m_.p[a];
  Vec2 step = climb ? ascent(a) : proposal(a) - from;
  double lo = 0.0, hi = 0.0;
  if (sliding) {
    const double here = m_.arc[a];
    lo = here - kArcGapFraction * (here - m_.neighbour_arc(a, 0));
    hi = here + kArcGapFraction * (m_.neighbour_arc(a, 1) - here);
  }
  for (int k = 0; k < options_.line_search; ++k, step = 0.5 * step) {
    Vec2 to = from + step;
    double to_arc = m_.arc[a];
    if (sliding) {
      const CurvePoint cp = closest_on_curve_range(geometry_.curves[m_.curve[a]], to, lo, hi);
      to = cp.p;
      to_arc = cp.arc;
    }
    if (to == from) return false;
    if (try_position(a, to, to_arc, old_min, old_error, old_outside, repair)) return true;
  }
  return false;
}

void MetricOps::absorb_changes() {
  const std::vector<std::uint8_t> changed = m_.take_dirty();
  for (auto* marks : {&smooth_pending_, &climb_pending_}) {
    marks->resize(changed.size(), 1);  // new vertices are pending
    for (std::size_t a = 0; a < changed.size(); ++a) (*marks)[a] |= changed[a];
  }
}

bool MetricOps::pending(std::vector<std::uint8_t>& marks, int a) const {
  const auto k = static_cast<std::size_t>(a);
  const bool due = (k < marks.size() && marks[k] != 0) || m_.dirty(a);
  if (k < marks.size()) marks[k] = 0;
  return due;
}

std::size_t MetricOps::smooth() {
  absorb_changes();
  std::size_t made = 0;
  for (int a = 0; a < m_.vertex_slots(); ++a)
    if (pending(smooth_pending_, a)) made += move_vertex(a, false) ? 1 : 0;
  counts_.moves += made;
  return made;
}

std::size_t MetricOps::climb(double below) {
  std::vector<unsigned char> mark(static_cast<std::size_t>(m_.vertex_slots()), 0);
  for (int t = 0; t < m_.triangle_slots(); ++t)
    if (m_.alive(t) && m_.quality(t) < below)
      for (int a : m_.v[t]) mark[static_cast<std::size_t>(a)] = 1;
  absorb_changes();
  std::size_t made = 0;
  for (int a = 0; a < m_.vertex_slots(); ++a)
    if (mark[static_cast<std::size_t>(a)] && pending(climb_pending_, a)) made += move_vertex(a, true) ? 1 : 0;
  counts_.moves += made;
  return made;
}

}  // namespace pdmesh::cleanup
