// OpenCL error codes by name, and the one check used after every OpenCL call.
#pragma once
#include <string_view>

#include "opencl/cl_include.hpp"

namespace pdmesh::ocl {

// "CL_OUT_OF_RESOURCES" for -5; "CL_UNKNOWN_ERROR" for codes not in the table.
const char* error_name(cl_int code);

// Throws DeviceError "<what> failed: CL_NAME (code)" when code != CL_SUCCESS. Passes the code
// through injected_fault() first.
void check(cl_int code, std::string_view what);

// Test-only fault injection (docs/robustness.md), compiled in: with PDMESH_TEST_FAIL_CL_AT=N (or
// N:CODE) in the environment, the Nth OpenCL result passed through here and every later one become
// CL_OUT_OF_RESOURCES (or CODE), as on a device that has been lost. Counted: every check(), and the
// successful transfers and launches, which skip check(). Without the variable: returns code.
cl_int injected_fault(cl_int code);

}  // namespace pdmesh::ocl
