// Where the tests that read cases/ find the source tree: PDMESH_TEST_SOURCE_DIR when it is set and not
// empty (the GPU kit, tools/gpu_kit, runs these test executables on a machine where the checkout they
// were built from does not exist, with its own copy of cases/), else the build's source directory.
#pragma once
#include <cstdlib>
#include <string>

namespace pdmesh::test {

inline std::string source_dir() {
  const char* dir = std::getenv("PDMESH_TEST_SOURCE_DIR");
  return dir != nullptr && *dir != '\0' ? std::string(dir) : std::string(PDMESH_SOURCE_DIR);
}

}  // namespace pdmesh::test
