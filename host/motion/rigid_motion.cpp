// Rigid poses and the motion path of a [motion] section (rigid_motion.hpp).
#include "motion/rigid_motion.hpp"

#include <cmath>

namespace pdmesh {

Vec2 RigidPose::apply(Vec2 p) const {
  const double c = std::cos(angle), s = std::sin(angle);
  const double dx = p.x - pivot.x, dy = p.y - pivot.y;
  return {pivot.x + c * dx - s * dy + shift.x, pivot.y + s * dx + c * dy + shift.y};
}

Vec2 RigidPose::apply_inverse(Vec2 p) const {
  const double c = std::cos(angle), s = std::sin(angle);
  const double dx = p.x - shift.x - pivot.x, dy = p.y - shift.y - pivot.y;
  return {pivot.x + c * dx + s * dy, pivot.y - s * dx + c * dy};
}

RigidPose pose_in_degrees(double rotate_deg, Vec2 pivot, Vec2 shift) {
  RigidPose p;
  p.angle = rotate_deg * M_PI / 180.0;
  p.pivot = pivot;
  p.shift = shift;
  return p;
}

RigidPose between(const RigidPose& a, const RigidPose& b, double s) {
  RigidPose p;
  p.pivot = a.pivot;
  p.angle = a.angle + s * (b.angle - a.angle);
  p.shift = {a.shift.x + s * (b.shift.x - a.shift.x), a.shift.y + s * (b.shift.y - a.shift.y)};
  return p;
}

MotionPath::MotionPath(const std::string& rotate_deg, std::array<double, 2> pivot,
                       const std::array<std::string, 2>& translate)
    : rotate_(rotate_deg, "motion.rotate"),
      pivot_{pivot[0], pivot[1]},
      tx_(translate[0], "motion.translate[0]"),
      ty_(translate[1], "motion.translate[1]") {}

RigidPose MotionPath::at(double t) const {
  const double angle = rotate_(t);  // first: its error is the one reported when several fail
  const double x = tx_(t);
  return pose_in_degrees(angle, pivot_, {x, ty_(t)});
}

}  // namespace pdmesh
