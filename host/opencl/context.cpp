// OpenCL context, queue, program builder (shared defines + common.cl + embedded kernels) and launch helper.
#include "opencl/context.hpp"

#include <cstdlib>
#include <cstring>

#include <fmt/format.h>

#include "core/embedded_kernels.hpp"
#include "core/errors.hpp"
#include "opencl/cl_errors.hpp"
#include "opencl/command_counts.hpp"

namespace pdmesh::ocl {

Context::Context(const DeviceInfo& device) : device_(device) {
  cl_int err = CL_SUCCESS;
  context_ = cl::Context(device_.handle, nullptr, nullptr, nullptr, &err);
  check(err, fmt::format("clCreateContext on {}", device_.name));
  // PDMESH_CL_PROFILING=1: a profiling queue, so that a tracer (PoCL's POCL_TRACING=text) records
  // each command's start and end (tools/bench/cl_trace_summary.py sums them per kernel). Only the
  // timestamps change: the commands and their order are the same.
  const char* profiling = std::getenv("PDMESH_CL_PROFILING");
  const cl_command_queue_properties properties =
      profiling != nullptr && std::strcmp(profiling, "1") == 0 ? CL_QUEUE_PROFILING_ENABLE : 0;
  queue_ = cl::CommandQueue(context_, device_.handle, properties, &err);
  check(err, fmt::format("clCreateCommandQueue on {}", device_.name));
}

const std::string& kernel_source(const std::string& file) {
  for (const auto& k : embedded_kernels())
    if (k.file == file) return k.source;
  throw DeviceError(fmt::format("kernel file '{}' is not embedded in this binary", file));
}

std::map<std::string, std::string> precision_defines(Precision precision, std::size_t work_group) {
  const bool dbl = precision == Precision::Double;
  // emplace from literals: GCC 12 warns falsely (-Wrestrict) on operator= of a ternary of literals.
  std::map<std::string, std::string> d;
  d.emplace("REAL", dbl ? "double" : "float");
  d.emplace("REAL2", dbl ? "double2" : "float2");
  d.emplace("PDMESH_DOUBLE", dbl ? "1" : "0");
  d.emplace("WG_SIZE", std::to_string(work_group));
  return d;
}

std::string program_source(const std::vector<std::string>& files, const std::map<std::string, std::string>& defines) {
  std::string source;
  for (const auto& [name, value] : defines) source += fmt::format("#define {} {}\n", name, value);
  if (defines.count("PDMESH_DOUBLE") && defines.at("PDMESH_DOUBLE") == "1")
    source += "#pragma OPENCL EXTENSION cl_khr_fp64 : enable\n";
  source += kernel_source("common.cl");
  for (const auto& f : files) {
    source += fmt::format("\n// ---- {} ----\n", f);
    source += kernel_source(f);
  }
  return source;
}

cl::Program Context::build(const std::vector<std::string>& files, const std::map<std::string, std::string>& defines,
                           const std::string& extra_options) {
  std::string label = "common.cl";
  for (const auto& f : files) label += ", " + f;
  std::string options = "-cl-std=CL1.2";
  if (!extra_options.empty()) options += " " + extra_options;
  return build_source(label, program_source(files, defines), options);
}

cl::Program Context::build_source(const std::string& label, const std::string& source, const std::string& options) {
  cl_int err = CL_SUCCESS;
  cl::Program program(context_, source, false, &err);
  check(err, fmt::format("clCreateProgramWithSource({})", label));
  err = program.build(std::vector<cl::Device>{device_.handle}, options.c_str());
  if (err != CL_SUCCESS) {
    std::string log;
    program.getBuildInfo(device_.handle, CL_PROGRAM_BUILD_LOG, &log);
    throw DeviceError(fmt::format("building OpenCL program from {} with options '{}' failed: {} ({})\nbuild log:\n{}",
                                  label, options, error_name(err), err, log.c_str()));
  }
  return program;
}

void launch(cl::CommandQueue& queue, cl::Kernel& kernel, const std::string& name, std::size_t count,
            std::size_t local) {
  if (count == 0) return;
  std::size_t global = (count + local - 1) / local * local;
  // The message is formatted only on failure: launches run every iteration.
  const cl_int err =
      injected_fault(queue.enqueueNDRangeKernel(kernel, cl::NullRange, cl::NDRange(global), cl::NDRange(local)));
  if (err != CL_SUCCESS) check(err, fmt::format("enqueue '{}' ({} work-items, local size {})", name, global, local));
  counting::launch();
}

void finish(cl::CommandQueue& queue, const std::string& what) {
  check(queue.finish(), what);
  counting::wait();
}

void flush(cl::CommandQueue& queue, const std::string& what) { check(queue.flush(), what); }

void copy_buffer(cl::CommandQueue& queue, cl::Buffer& from, cl::Buffer& to, std::size_t bytes,
                 const std::string& what) {
  check(queue.enqueueCopyBuffer(from, to, 0, 0, bytes), what);
  counting::copy();
}

void fill_zero(cl::CommandQueue& queue, cl::Buffer& buffer, std::size_t bytes, const std::string& what) {
  check(queue.enqueueFillBuffer(buffer, cl_int{0}, 0, bytes), what);
  counting::copy();
}

}  // namespace pdmesh::ocl
