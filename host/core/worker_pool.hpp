// WorkerPool: the helper threads of parallel_for, started once and kept for the process.
//
// Why not a thread per call: creating a thread takes glibc's TLS lock (_dl_allocate_tls_init), which
// dlopen holds for the whole load. The OpenCL backend is set up on its own thread while the spacing
// field is built, and PoCL's dlopen of LLVM and clang (170 MB) takes ~0.15 s when the page cache has
// dropped them (this machine drops them within a minute): every parallel_for of the spacing phase
// waited for it before its helper could start (docs/journal/). The pool's
// threads are started before the backend (start_workers() in run_mesh), so no call creates one then.
#pragma once
#include <atomic>
#include <condition_variable>
#include <cstddef>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace pdmesh {

class WorkerPool {
 public:
  // The process's pool: hardware_concurrency() - 1 helpers, started on the first call and kept (never
  // destroyed) until the process ends.
  static WorkerPool& instance();

  explicit WorkerPool(std::size_t helpers);
  ~WorkerPool();
  WorkerPool(const WorkerPool&) = delete;
  WorkerPool& operator=(const WorkerPool&) = delete;

  std::size_t helpers() const { return threads_.size(); }

  // Runs job(0) on the calling thread and job(1), ..., job(count) on `count` helpers (count <=
  // helpers()), and returns once all have returned; job must not throw. Returns false without
  // running anything when the pool is already serving another call (a parallel_for on another
  // thread, or one nested in a job), when count > helpers(), or in a child process forked after the
  // pool started (its helpers are the parent's): the caller then makes threads of its own.
  bool run(std::size_t count, const std::function<void(std::size_t)>& job);

 private:
  void work(std::size_t index);

  std::vector<std::thread> threads_;
  std::atomic<bool> busy_{false};  // set by the call being served (not a mutex: a nested call on the
                                   // same thread must see it taken, and may not try_lock a mutex it holds)
  std::mutex mutex_;
  std::condition_variable wake_, done_;
  const std::function<void(std::size_t)>* job_ = nullptr;
  std::size_t count_ = 0;       // helpers 1..count_ take part in the current job
  std::size_t generation_ = 0;  // bumped for every job
  std::size_t pending_ = 0;     // helpers of the current job still running
  bool stop_ = false;
  int pid_;  // the process whose threads these are (getpid() at construction)
};

// Starts the process's pool now (see the header comment for why this matters before a dlopen).
void start_workers();

}  // namespace pdmesh
