// Debug trace of one simulation iteration (PDMESH_SIM_TRACE=FIRST-LAST on stderr): the nodes with
// the largest |F|, their kind, r0 and dt_i, and every neighbour with r/sigma and whether it sees them.
#pragma once
#include <cstdio>

#include "sim/step_backend.hpp"

namespace pdmesh {

struct TraceRange {
  int first = 0, last = -1;  // iterations to trace (inclusive); empty when last < first
  static TraceRange from_environment();
  bool covers(int iteration) const { return iteration >= first && iteration <= last; }
};

// TEMPORARY (measurements): PDMESH_SIM_STABILITY=c and PDMESH_SIM_R0_ANY=1 override the options.
void debug_overrides(ForceParams& params);

void trace_step(std::FILE* out, int iteration, const SimParticles& p, const NeighbourList& list,
                const ForceResult& forces, const MoveResult& moves, double dt_gm2, double cutoff, int top);

}  // namespace pdmesh
