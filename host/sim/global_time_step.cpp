// The global maximum time step rule; see global_time_step.hpp.
#include "sim/global_time_step.hpp"

namespace pdmesh {

int GlobalTimeStep::update(double max_force) {
  const std::optional<double> before = previous_;
  previous_ = max_force;
  if (!before) return 0;
  if (max_force < *before) {
    if (++consecutive_decreases_ == kRunLength) {
      dt_ *= kGrow;
      consecutive_decreases_ = 0;
      increases_ = 0;
      return +1;
    }
    return 0;
  }
  consecutive_decreases_ = 0;
  if (max_force > *before && ++increases_ == kRunLength) {
    dt_ *= kShrink;
    increases_ = 0;
    return -1;
  }
  return 0;
}

}  // namespace pdmesh
