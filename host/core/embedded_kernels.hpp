// The OpenCL kernel sources of kernels/*.cl, embedded at build time (tools/cmake/EmbedKernels.cmake).
#pragma once
#include <string>
#include <vector>

namespace pdmesh {

struct EmbeddedKernel {
  std::string file;    // e.g. "forces.cl"
  std::string source;  // the file's text
};

// Every kernels/*.cl file, in file-name order.
const std::vector<EmbeddedKernel>& embedded_kernels();

}  // namespace pdmesh
