// Per-thread counts of the OpenCL commands the wrapper enqueues; see command_counts.hpp.
#include "opencl/command_counts.hpp"

namespace pdmesh::ocl {
namespace {

thread_local CommandCounts t_counts;

}  // namespace

CommandCounts operator-(const CommandCounts& a, const CommandCounts& b) {
  CommandCounts d;
  d.launches = a.launches - b.launches;
  d.reads = a.reads - b.reads;
  d.writes = a.writes - b.writes;
  d.copies = a.copies - b.copies;
  d.waits = a.waits - b.waits;
  d.bytes_read = a.bytes_read - b.bytes_read;
  d.bytes_written = a.bytes_written - b.bytes_written;
  return d;
}

CommandCounts operator+(const CommandCounts& a, const CommandCounts& b) {
  CommandCounts d;
  d.launches = a.launches + b.launches;
  d.reads = a.reads + b.reads;
  d.writes = a.writes + b.writes;
  d.copies = a.copies + b.copies;
  d.waits = a.waits + b.waits;
  d.bytes_read = a.bytes_read + b.bytes_read;
  d.bytes_written = a.bytes_written + b.bytes_written;
  return d;
}

CommandCounts command_counts() { return t_counts; }

namespace counting {

void launch() { ++t_counts.launches; }

void read(std::size_t bytes, bool blocking) {
  ++t_counts.reads;
  t_counts.bytes_read += bytes;
  if (blocking) ++t_counts.waits;
}

void write(std::size_t bytes, bool blocking) {
  ++t_counts.writes;
  t_counts.bytes_written += bytes;
  if (blocking) ++t_counts.waits;
}

void copy() { ++t_counts.copies; }

void wait() { ++t_counts.waits; }

}  // namespace counting
}  // namespace pdmesh::ocl
