// The environment variables that change what a command does, checked together before it starts
// (docs/cli.md, "Environment"), so that a malformed value stops the command before it writes
// anything, not where a stage first reads the variable, mid-run.
#pragma once

namespace pdmesh {

// Reads PDMESH_FORCE_LOOP, PDMESH_MEASURE_OVERLAP, PDMESH_KERNEL_PROFILE, PDMESH_ROW_LOCALITY and
// PDMESH_SIM_TRACE through the parsers their readers use and throws InputError, naming the variable
// and the value, for the first that is malformed (PDMESH_KERNEL_PROFILE: its file's folder must
// exist). The switches that are on when set (the traces, the population profile) take any value; the
// PDMESH_TEST_* variables are the tests' and are not checked.
void check_environment();

}  // namespace pdmesh
