// The pdmesh command: app/cli/cli parses the command line, runs the command and turns typed errors into
// exit codes (bad input 2, other pdmesh errors 1, anything unexpected 1 as an internal error).
#include <cstdlib>
#if defined(__GLIBC__)
#include <malloc.h>
#endif

#include "app/cli/cli.hpp"

int main(int argc, char** argv) {
#if defined(__GLIBC__)
  // Blocks of 512 KiB and more come from the system and go back to it when freed. glibc's default
  // raises this threshold to the largest block freed so far (up to 32 MB), after which a run's node
  // arrays, device buffers (PoCL's are host memory) and each convergence check's triangulation are
  // carved from its heaps, and the pages they leave stay resident: at 264k nodes the simulation held
  // ~120 MB more than it used (docs/journal/2026-12-02c-sim-memory.md). The cost is a page fault per
  // page of each such block when it is first written (~3% more CPU at 264k nodes).
  mallopt(M_MMAP_THRESHOLD, 512 * 1024);
#endif
  return pdmesh::run_command_line(argc, argv);
}
