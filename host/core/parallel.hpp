// parallel_for: splits an index range among a few threads for loops whose iterations are independent
// (each writes only its own outputs), so the result does not depend on the thread count.
#pragma once
#include <algorithm>
#include <cstddef>
#include <exception>
#include <thread>
#include <vector>

namespace pdmesh {

// Calls body(i) for every i in [0, n), on up to max_threads threads (at most the hardware's) in
// contiguous chunks of at least min_chunk; small ranges run on the calling thread. An exception
// thrown by body on any thread is rethrown here after all threads have finished (the first by chunk).
template <class Body>
void parallel_for(std::size_t n, const Body& body, std::size_t min_chunk = 4096, std::size_t max_threads = 8) {
  const std::size_t chunks = (n + min_chunk - 1) / std::max<std::size_t>(1, min_chunk);
  // hardware_concurrency() reads /sys on Linux: ask once.
  static const std::size_t hardware = std::max(1u, std::thread::hardware_concurrency());
  const std::size_t threads = chunks <= 1 ? 1 : std::min({hardware, max_threads, chunks});
  if (threads <= 1) {
    for (std::size_t i = 0; i < n; ++i) body(i);
    return;
  }
  std::vector<std::exception_ptr> errors(threads);
  const std::size_t chunk = (n + threads - 1) / threads;
  auto run = [&](std::size_t t) {
    try {
      const std::size_t end = std::min(n, (t + 1) * chunk);
      for (std::size_t i = t * chunk; i < end; ++i) body(i);
    } catch (...) {
      errors[t] = std::current_exception();
    }
  };
  std::vector<std::thread> workers;
  for (std::size_t t = 1; t < threads; ++t) workers.emplace_back(run, t);
  run(0);
  for (std::thread& w : workers) w.join();
  for (const std::exception_ptr& e : errors)
    if (e) std::rethrow_exception(e);
}

}  // namespace pdmesh
