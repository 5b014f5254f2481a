// Runs the pdmesh binary (PDMESH_BINARY) with arguments and captures its exit status and output,
// for tests of the command line.
#pragma once
#include <sys/wait.h>

#include <cstdio>
#include <string>

namespace pdmesh_test {

struct Result {
  int status = -1;
  std::string output;  // stdout and stderr together
};

// `arguments` is pasted into a shell command line: quote paths. `environment` (e.g. "VAR=value")
// is set for this run only.
inline Result run_pdmesh(const std::string& arguments, const std::string& environment = "") {
  const std::string command =
      (environment.empty() ? "" : "env " + environment + " ") + "'" + PDMESH_BINARY + "' " + arguments + " 2>&1";
  Result r;
  FILE* pipe = ::popen(command.c_str(), "r");
  if (pipe == nullptr) return r;
  char buffer[4096];
  std::size_t n = 0;
  while ((n = std::fread(buffer, 1, sizeof buffer, pipe)) > 0) r.output.append(buffer, n);
  const int raw = ::pclose(pipe);
  r.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
  return r;
}

}  // namespace pdmesh_test
