// The pdmesh command: app/cli/cli parses the command line, runs the command and turns typed errors into
// exit codes (bad input 2, other pdmesh errors 1, anything unexpected 1 as an internal error).
#include "app/cli/cli.hpp"

int main(int argc, char** argv) { return pdmesh::run_command_line(argc, argv); }
