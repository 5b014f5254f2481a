// Counts of the OpenCL commands pdmesh enqueues through its wrapper (ocl::launch, Buffer::upload and
// download, ocl::finish, ocl::copy_buffer, ocl::fill_zero), so that launches, transfers and host waits
// per iteration are measured rather than tallied by hand (`pdmesh bench`, docs/opencl.md). Per thread:
// a run enqueues from one thread, and a caller takes the difference of two snapshots around what it
// measures. Not counted: the canary tails of test contexts (Buffer::check_canary), which are test
// instrumentation, and the final wait of a run's destructor.
#pragma once
#include <cstddef>
#include <cstdint>

namespace pdmesh::ocl {

struct CommandCounts {
  std::uint64_t launches = 0;  // clEnqueueNDRangeKernel
  std::uint64_t reads = 0;     // clEnqueueReadBuffer (device to host)
  std::uint64_t writes = 0;    // clEnqueueWriteBuffer (host to device)
  std::uint64_t copies = 0;    // clEnqueueCopyBuffer and clEnqueueFillBuffer (device memory only)
  std::uint64_t waits = 0;     // the host blocks until the device is done: clFinish, a blocking read or write
  std::uint64_t bytes_read = 0, bytes_written = 0;
};
CommandCounts operator-(const CommandCounts& a, const CommandCounts& b);
CommandCounts operator+(const CommandCounts& a, const CommandCounts& b);

// This thread's totals since it started.
CommandCounts command_counts();

// Called by the wrapper after each successful enqueue (nothing else should).
namespace counting {
void launch();
void read(std::size_t bytes, bool blocking);
void write(std::size_t bytes, bool blocking);
void copy();
void wait();
}  // namespace counting

}  // namespace pdmesh::ocl
