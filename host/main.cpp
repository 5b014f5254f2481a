// The pdmesh command: parses the command line (app/cli) and turns typed errors into exit codes:
// bad input 2, other pdmesh errors 1, anything unexpected 1 as an internal error.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <exception>
#include <fmt/format.h>

#include "app/cli.hpp"
#include "app/exit_codes.hpp"
#include "core/errors.hpp"

int main(int argc, char** argv) {
  try {
    pdmesh::Cli cli;
    try {
      cli.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
      // --help and --version arrive here too, with exit code 0.
      return cli.app().exit(e) == 0 ? pdmesh::kExitOk : pdmesh::kExitInput;
    }
    return cli.run();
  } catch (const pdmesh::InputError& e) {
    fmt::print(stderr, "pdmesh: error: {}\n", e.what());
    return pdmesh::kExitInput;
  } catch (const pdmesh::Error& e) {
    fmt::print(stderr, "pdmesh: error: {}\n", e.what());
    return pdmesh::kExitFailure;
  } catch (const std::exception& e) {
    fmt::print(stderr, "pdmesh: internal error: {}\n", e.what());
    return pdmesh::kExitFailure;
  }
}
