// Rigid poses of the moving curves of a [motion] section (docs/motion.md): a rotation about a pivot
// followed by a translation, as functions of time, and the map between two poses.
#pragma once
#include <array>
#include <string>

#include "core/vec2.hpp"
#include "motion/time_expression.hpp"

namespace pdmesh {

// x -> pivot + R(angle) (x - pivot) + shift, angle in radians, counter-clockwise positive.
struct RigidPose {
  double angle = 0.0;
  Vec2 pivot{0.0, 0.0};
  Vec2 shift{0.0, 0.0};
  Vec2 apply(Vec2 p) const;
  Vec2 apply_inverse(Vec2 p) const;
  bool identity() const { return angle == 0.0 && shift.x == 0.0 && shift.y == 0.0; }
};

// The pose of a rotation by rotate_deg degrees (counter-clockwise) about pivot, then a shift: the one
// conversion from degrees, which MotionPath and Python's MovingMesher share (the same poses bit for bit).
RigidPose pose_in_degrees(double rotate_deg, Vec2 pivot, Vec2 shift);

// The pose part way from a to b (same pivot): angle and shift interpolated linearly, s in [0, 1].
RigidPose between(const RigidPose& a, const RigidPose& b, double s);

// The map that takes a point placed by pose `from` to where pose `to` places it: to(from^-1(p)).
struct PoseChange {
  RigidPose from, to;
  Vec2 operator()(Vec2 p) const { return to.apply(from.apply_inverse(p)); }
};

// rotate(t) in degrees about pivot, translate = (x(t), y(t)). The constructor parses the three
// expressions (InputError naming the key); at(t) evaluates them (InputError when not finite).
class MotionPath {
 public:
  MotionPath(const std::string& rotate_deg, std::array<double, 2> pivot, const std::array<std::string, 2>& translate);
  RigidPose at(double t) const;

 private:
  TimeExpression rotate_;
  Vec2 pivot_;
  TimeExpression tx_, ty_;
};

}  // namespace pdmesh
