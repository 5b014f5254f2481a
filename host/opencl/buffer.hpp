// A typed, named device buffer (RAII through cl::Buffer). Uploads and downloads check sizes and
// every error names the buffer, so a failure reads "download of 'forces' failed: CL_OUT_OF_RESOURCES (-5)";
// every transfer is counted (command_counts.hpp).
// With Context::set_canary_tail (tests) each buffer carries a sentinel tail checked on every download.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "core/errors.hpp"
#include "opencl/cl_errors.hpp"
#include "opencl/command_counts.hpp"
#include "opencl/context.hpp"

namespace pdmesh::ocl {

template <typename T>
class Buffer {
 public:
  Buffer() = default;
  Buffer(Context& ctx, std::string name, std::size_t count, cl_mem_flags flags = CL_MEM_READ_WRITE)
      : name_(std::move(name)), count_(count), tail_(ctx.canary_tail()) {
    cl_int err = CL_SUCCESS;
    // A zero-sized cl::Buffer is invalid; keep one element so kernels always get a valid pointer
    // (with a canary tail the tail starts right at count_, so even a 0-element buffer detects a write).
    std::size_t bytes = sizeof(T) * (tail_ ? count_ + tail_ : count_ ? count_ : 1);
    if (bytes > ctx.device().max_allocation)
      throw LimitError(
          fmt::format("buffer '{}' needs {} bytes, more than the largest allocation {} allows "
                      "(CL_DEVICE_MAX_MEM_ALLOC_SIZE, {} bytes): use --precision float (half the bytes), "
                      "--device host (the host reference) or a coarser spacing (fewer nodes)",
                      name_, bytes, ctx.device().name, ctx.device().max_allocation));
    buffer_ = cl::Buffer(ctx.context(), flags, bytes, nullptr, &err);
    check(err, fmt::format("allocating buffer '{}' ({} bytes)", name_, bytes));
    if (tail_) {
      const std::vector<std::uint8_t> sentinel(sizeof(T) * tail_, kCanaryByte);
      check(ctx.queue().enqueueWriteBuffer(buffer_, CL_TRUE, sizeof(T) * count_, sentinel.size(), sentinel.data()),
            fmt::format("writing the canary tail of '{}'", name_));
    }
  }

  // A read-only buffer over `host` itself (CL_MEM_USE_HOST_PTR), no copy made: for a CPU device,
  // whose memory is the host's, so that an array the host keeps anyway is not held twice. `host` must
  // stay alive and unchanged while the buffer is used. Not with a canary tail (a copy then).
  static Buffer over_host(Context& ctx, std::string name, const std::vector<T>& host) {
    if (ctx.canary_tail() || host.empty()) {
      Buffer b(ctx, std::move(name), host.size());
      b.upload(ctx.queue(), host);
      return b;
    }
    Buffer b;
    b.name_ = std::move(name);
    b.count_ = host.size();
    cl_int err = CL_SUCCESS;
    b.buffer_ = cl::Buffer(ctx.context(), CL_MEM_READ_ONLY | CL_MEM_USE_HOST_PTR, sizeof(T) * host.size(),
                           const_cast<T*>(host.data()), &err);
    check(err, fmt::format("allocating buffer '{}' over the host's array ({} bytes)", b.name_, b.bytes()));
    return b;
  }

  const std::string& name() const { return name_; }
  std::size_t size() const { return count_; }
  std::size_t bytes() const { return sizeof(T) * count_; }
  cl::Buffer& get() { return buffer_; }

  void upload(cl::CommandQueue& q, const std::vector<T>& host, bool blocking = true) {
    upload(q, host.data(), host.size(), blocking);
  }
  void upload(cl::CommandQueue& q, const T* data, std::size_t count, bool blocking = true) {
    if (count > count_)
      throw DeviceError(fmt::format("upload of {} elements into buffer '{}' of {}", count, name_, count_));
    if (count == 0) return;
    // The message is formatted only on failure: transfers run every iteration.
    const cl_int err =
        injected_fault(q.enqueueWriteBuffer(buffer_, blocking ? CL_TRUE : CL_FALSE, 0, sizeof(T) * count, data));
    if (err != CL_SUCCESS) check(err, fmt::format("upload to '{}'", name_));
    counting::write(sizeof(T) * count, blocking);
  }
  // Non-blocking (blocking = false): `host` is sized now and filled once the queue is synchronised.
  void download(cl::CommandQueue& q, std::vector<T>& host, std::size_t count, bool blocking = true) {
    if (count > count_)
      throw DeviceError(fmt::format("download of {} elements from buffer '{}' of {}", count, name_, count_));
    host.resize(count);
    if (tail_) check_canary(q);
    if (count == 0) return;
    const cl_int err =
        injected_fault(q.enqueueReadBuffer(buffer_, blocking ? CL_TRUE : CL_FALSE, 0, sizeof(T) * count, host.data()));
    if (err != CL_SUCCESS) check(err, fmt::format("download from '{}'", name_));
    counting::read(sizeof(T) * count, blocking);
  }
  void download(cl::CommandQueue& q, std::vector<T>& host) { download(q, host, count_); }

  // Throws DeviceError naming the buffer and the first overwritten element past its end when the
  // canary tail (Context::set_canary_tail) is no longer the sentinel; no-op without a tail.
  void check_canary(cl::CommandQueue& q) {
    if (!tail_) return;
    std::vector<std::uint8_t> got(sizeof(T) * tail_);
    check(q.enqueueReadBuffer(buffer_, CL_TRUE, sizeof(T) * count_, got.size(), got.data()),
          fmt::format("reading the canary tail of '{}'", name_));
    for (std::size_t b = 0; b < got.size(); ++b)
      if (got[b] != kCanaryByte)
        throw DeviceError(fmt::format("buffer '{}' of {} elements: element {} past its end was overwritten", name_,
                                      count_, count_ + b / sizeof(T)));
  }
  std::size_t canary_tail() const { return tail_; }

 private:
  static constexpr std::uint8_t kCanaryByte = 0xA5;
  std::string name_;
  std::size_t count_ = 0;
  std::size_t tail_ = 0;  // canary elements after count_ (tests only)
  cl::Buffer buffer_;
};

}  // namespace pdmesh::ocl
