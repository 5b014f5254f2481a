// The stopping rule's options the convergence tests share: a measurement every 10 iterations, a
// 40-iteration window, small tolerances, so that a test's made-up measurements reach a decision fast.
#pragma once
#include "sim/convergence.hpp"

namespace pdmesh_test {

inline pdmesh::ConvergenceOptions small_convergence_options() {
  pdmesh::ConvergenceOptions o;
  o.enabled = true;
  o.check_every = 10;
  o.window = 40;
  o.aspect_tolerance = 5e-4;
  o.angle_tolerance = 0.25;
  o.min_iterations = 40;
  return o;
}

}  // namespace pdmesh_test
