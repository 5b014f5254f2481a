// parallel_for: splits an index range among a few threads for loops whose iterations are independent
// (each writes only its own outputs), so the result does not depend on the thread count.
#pragma once
#include <algorithm>
#include <atomic>
#include <cstddef>
#include <exception>
#include <functional>
#include <thread>
#include <vector>

#include "core/interrupt.hpp"
#include "core/worker_pool.hpp"

namespace pdmesh {

// parallel_for_scratch: parallel_for whose body also gets a Scratch that belongs to the thread running
// it, default-constructed once per thread and call (a local of that thread, not a thread_local):
// body(scratch, i). For per-thread buffers and search seeds carried from one index to the next.
// Why not thread_local: the first use of a thread_local with a destructor in a thread registers it
// through glibc's __cxa_thread_atexit_impl, which takes the dynamic loader's lock; while the OpenCL
// backend's thread is inside dlopen (PoCL and LLVM, 170 MB, read from disk when the page cache has
// dropped them) that lock is held for up to ~100 ms, and the spacing phase's threads stalled behind
// it (docs/journal/; creating a thread waits for it too, hence the pool of
// core/worker_pool.hpp). Which thread and scratch serve an index changes nothing when body(scratch,
// i)'s result does not depend on what an earlier index left in the scratch.
template <class Scratch, class Body>
void parallel_for_scratch(std::size_t n, const Body& body, std::size_t min_chunk = 4096, std::size_t max_threads = 8) {
  const std::size_t chunks = (n + min_chunk - 1) / std::max<std::size_t>(1, min_chunk);
  // hardware_concurrency() reads /sys on Linux: ask once.
  static const std::size_t hardware = std::max(1u, std::thread::hardware_concurrency());
  const std::size_t threads = chunks <= 1 ? 1 : std::min({hardware, max_threads, chunks});
  // A stop request (core/interrupt) ends the loop between blocks with Interrupted, unless the caller
  // is shielded (the helpers run on other threads: the caller's shield is passed on by hand).
  const bool poll = !interrupt_shielded();
  if (threads <= 1) {
    Scratch scratch{};
    for (std::size_t i = 0; i < n; ++i) {
      if (poll && (i & 1023) == 0) check_interrupt();
      body(scratch, i);
    }
    return;
  }
  // Blocks small enough that the last ones even out the threads' finishing times (8 per thread), and
  // at most min_chunk so that a block is never more than the caller's idea of a worthwhile chunk.
  const std::size_t block = std::max<std::size_t>(1, std::min(min_chunk, n / (8 * threads)));
  std::atomic<std::size_t> next{0};
  std::atomic<bool> failed{false};
  std::vector<std::exception_ptr> errors(threads);
  std::vector<std::size_t> error_block(threads, n);
  auto run = [&](std::size_t t) {
    std::size_t begin = 0;
    try {
      Scratch scratch{};
      while (!failed.load(std::memory_order_relaxed)) {
        begin = next.fetch_add(block, std::memory_order_relaxed);
        if (begin >= n) break;
        if (poll && interrupt_flag().load(std::memory_order_relaxed)) throw_interrupted();
        const std::size_t end = std::min(n, begin + block);
        for (std::size_t i = begin; i < end; ++i) body(scratch, i);
      }
    } catch (...) {
      errors[t] = std::current_exception();
      error_block[t] = begin;
      failed.store(true, std::memory_order_relaxed);
    }
  };
  // The helpers come from the process's pool (core/worker_pool.hpp: no thread is created per call),
  // or, when the pool is serving another call or has too few, from threads of this call's own.
  if (!WorkerPool::instance().run(threads - 1, run)) {
    std::vector<std::thread> workers;
    for (std::size_t t = 1; t < threads; ++t) workers.emplace_back(run, t);
    run(0);
    for (std::thread& w : workers) w.join();
  }
  std::size_t first = threads;
  for (std::size_t t = 0; t < threads; ++t)
    if (errors[t] && (first == threads || error_block[t] < error_block[first])) first = t;
  if (first < threads) std::rethrow_exception(errors[first]);
}

namespace detail {
struct NoScratch {};
}  // namespace detail

// Calls body(i) for every i in [0, n), on up to max_threads threads (at most the hardware's) when the
// range holds at least two chunks of min_chunk; smaller ranges run on the calling thread. The threads
// take blocks of indices from a shared counter rather than equal shares fixed up front: the cost of an
// index varies along a range (an eq. 3.6 point near a curve costs several times one far from every
// curve), and with equal shares one of two threads sat idle for a fifth of the spacing phase on
// 30P30N. Which thread runs an index changes nothing: each body(i) writes only its own outputs. An
// exception thrown by body is rethrown here after all threads have finished: the one of the lowest
// block that threw (the threads stop taking blocks once one has thrown).
template <class Body>
void parallel_for(std::size_t n, const Body& body, std::size_t min_chunk = 4096, std::size_t max_threads = 8) {
  parallel_for_scratch<detail::NoScratch>(
      n, [&body](detail::NoScratch&, std::size_t i) { body(i); }, min_chunk, max_threads);
}

}  // namespace pdmesh
