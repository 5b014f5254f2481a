// Debug aids of the simulation driver: a trace of chosen iterations (PDMESH_SIM_TRACE=FIRST-LAST, on
// stderr: the 3 nodes with the largest |F|, their kind, r0, dt_i and what limited it, and every
// neighbour with r/sigma and whether it sees them back).
#pragma once
#include <cstdio>

#include "sim/step_backend.hpp"

namespace pdmesh {

struct TraceRange {
  int first = 0, last = -1;  // iterations to trace (inclusive); empty when last < first
  // PDMESH_SIM_TRACE: empty when unset; a value other than FIRST-LAST with 0 <= FIRST <= LAST throws
  // InputError naming the variable and the value.
  static TraceRange from_environment();
  bool covers(int iteration) const { return iteration >= first && iteration <= last; }
};

void trace_step(std::FILE* out, int iteration, const SimParticles& p, const NeighbourList& list,
                const ForceResult& forces, const MoveResult& moves, double dt_gm2, double cutoff, int top);

}  // namespace pdmesh
