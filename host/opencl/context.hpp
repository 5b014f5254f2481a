// One OpenCL device in use: its context, in-order queue and capabilities, plus the program builder
// that prepends pdmesh's shared defines to the embedded kernels/*.cl sources.
#pragma once
#include <map>
#include <string>
#include <vector>

#include "opencl/cl_include.hpp"
#include "opencl/devices.hpp"

namespace pdmesh::ocl {

enum class Precision { Double, Float };
// The shape of the simulation program's force loop (step_program.hpp, resolve_force_loop).
enum class ForceLoop { Auto, Vector, Scalar };

class Context {
 public:
  explicit Context(const DeviceInfo& device);

  const DeviceInfo& device() const { return device_; }
  cl::Context& context() { return context_; }
  cl::CommandQueue& queue() { return queue_; }

  // Test hook (0, off, in production): every Buffer allocated afterwards gets this many extra
  // elements after its end, filled with a sentinel and checked on each download, so a kernel that
  // writes past an output's end fails the call with a DeviceError naming the buffer (buffer.hpp).
  void set_canary_tail(std::size_t elements) { canary_tail_ = elements; }
  std::size_t canary_tail() const { return canary_tail_; }

  // Builds kernels/common.cl followed by the named kernels/*.cl files (embedded at build time), with
  // "#define NAME VALUE" lines for every entry of `defines` prepended, and -cl-std=CL1.2.
  // Throws DeviceError naming the files, the options and the build log on failure.
  cl::Program build(const std::vector<std::string>& files, const std::map<std::string, std::string>& defines,
                    const std::string& extra_options = "");

  // Builds a program from literal source text (for tests of the builder itself).
  cl::Program build_source(const std::string& label, const std::string& source, const std::string& options);

 private:
  DeviceInfo device_;
  cl::Context context_;
  cl::CommandQueue queue_;
  std::size_t canary_tail_ = 0;
};

// The text of one embedded kernel file; throws DeviceError if it was not embedded.
const std::string& kernel_source(const std::string& file);

// The source Context::build compiles: the "#define NAME VALUE" lines, the fp64 pragma when
// PDMESH_DOUBLE is 1, common.cl, then each file under a "// ---- FILE ----" line.
std::string program_source(const std::vector<std::string>& files, const std::map<std::string, std::string>& defines);

// "#define REAL double" etc.: the common defines for a precision and work-group size.
std::map<std::string, std::string> precision_defines(Precision precision, std::size_t work_group);

// Runs `kernel` over `count` work-items in groups of `local` (the global size is rounded up to a multiple
// of `local`; kernels skip the extra items). Errors name the kernel.
void launch(cl::CommandQueue& queue, cl::Kernel& kernel, const std::string& name, std::size_t count, std::size_t local);

// The other commands the simulation enqueues, checked (errors name `what`) and counted
// (command_counts.hpp) like launch and the Buffer transfers: clFinish (a host wait), a device-side
// copy of the first `bytes` bytes, and filling the first `bytes` bytes with zero ints (bytes > 0).
void finish(cl::CommandQueue& queue, const std::string& what);
// clFlush: the commands enqueued so far are submitted to the device without a wait (not counted).
void flush(cl::CommandQueue& queue, const std::string& what);
void copy_buffer(cl::CommandQueue& queue, cl::Buffer& from, cl::Buffer& to, std::size_t bytes, const std::string& what);
void fill_zero(cl::CommandQueue& queue, cl::Buffer& buffer, std::size_t bytes, const std::string& what);

}  // namespace pdmesh::ocl
