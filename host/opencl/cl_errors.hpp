// OpenCL error codes by name, and the one check used after every OpenCL call.
#pragma once
#include <string_view>

#include "opencl/cl_include.hpp"

namespace pdmesh::ocl {

// "CL_OUT_OF_RESOURCES" for -5; "CL_UNKNOWN_ERROR" for codes not in the table.
const char* error_name(cl_int code);

// Throws DeviceError "<what> failed: CL_NAME (code)" when code != CL_SUCCESS.
void check(cl_int code, std::string_view what);

}  // namespace pdmesh::ocl
