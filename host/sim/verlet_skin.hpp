// The Verlet skin of a device run (SimOptions::verlet_skin): the rows hold every pair within
// cutoff q (1 + skin), so a larger skin lasts more iterations between neighbour-list builds but makes
// every row, every step's traffic and the run's peak memory larger. The skin never changes a result.
#pragma once
#include <cstddef>

namespace pdmesh {

// Without momentum (the thesis and long presets) the nodes move little per iteration and a small
// skin lasts (docs/opencl.md, "Neighbour lists: Verlet skin").
inline constexpr double kVerletSkin = 0.3;

// With momentum the nodes move farther per iteration early in a run and use up a 0.3 skin ~3x as
// often. Which larger skin pays depends on the node count: a build costs a few steps, and a larger
// skin makes both the steps and the builds dearer. Small runs gain a little from 0.6; from
// kSmallRunNodes up 0.5 is the cheapest or close to it, and a larger skin would take the whole
// command's peak memory past 500 B per node at millions of nodes (docs/performance.md, "The Verlet
// skin by size", has the measurements).
inline constexpr double kSmallRunVerletSkin = 0.6;
inline constexpr double kMomentumVerletSkin = 0.5;
inline constexpr std::size_t kSmallRunNodes = 100'000;  // below: kSmallRunVerletSkin

// simulation.verlet_skin = "auto", for a run of `nodes` nodes at its start (population control
// changes the count by a few per cent at most; the skin stays the run's).
inline double auto_verlet_skin(double momentum, std::size_t nodes) {
  if (!(momentum > 0.0)) return kVerletSkin;
  return nodes < kSmallRunNodes ? kSmallRunVerletSkin : kMomentumVerletSkin;
}

}  // namespace pdmesh
