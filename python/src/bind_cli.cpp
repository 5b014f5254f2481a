// pdmesh._core.main: the `pdmesh` command line, the same code as the C++ binary's main(), for the
// console script and `python -m pdmesh`.
#include <cstdio>
#include <nanobind/stl/string.h>
#include <nanobind/stl/vector.h>

#include "app/cli/cli.hpp"
#include "bindings.hpp"

namespace pdmesh::py {

void bind_cli(nb::module_& m) {
  m.def(
      "main",
      [](const std::vector<std::string>& args) {
        std::vector<const char*> argv;
        for (const std::string& a : args) argv.push_back(a.c_str());
        // The command writes through C stdio; what Python buffered was flushed by the caller.
        nb::gil_scoped_release release;
        const int status = run_command_line(static_cast<int>(argv.size()), argv.data());
        std::fflush(stdout);
        std::fflush(stderr);
        return status;
      },
      nb::arg("argv"), "Runs the pdmesh command line (argv[0] is the program name); returns the exit status.");
}

}  // namespace pdmesh::py
