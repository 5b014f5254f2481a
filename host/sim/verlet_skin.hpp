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
// often. Which larger skin pays depends on the node count (PoCL, 2 cores; docs/performance.md,
// "The Verlet skin by size"): the lists are rebuilt when the node that has moved farthest has used up
// its skin, a build costs ~4-5 steps, and a larger skin makes both the steps and the builds dearer.
// The whole command's CPU against 0.5, paired runs: at 11-25k nodes 0.6 0.985-0.993x (0.8
// 0.986-1.009x; a gain of the order of a loaded machine's noise), the rows' memory there a few MB; at 265k 0.5 is the
// cheapest (0.6 1.023x, 0.8 1.026x), at 1M too (0.8 1.003-1.043x). At 5.3M 0.5 makes 23 builds, 0.6 18 and 0.8 10, and
// 0.8 saves 2.5-5.5 % of the time, but the whole command's peak is 485 B per node at 0.5, 515 at 0.6 and 549 at 0.8
// (issue 41's bound: 500 B per node + 300 MB, 557 B there): the memory goes first, so 0.5 from kSmallRunNodes up.
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
