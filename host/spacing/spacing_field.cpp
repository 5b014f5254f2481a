// The SpacingField base: the default many-point evaluation, and the thread split of large batches.
#include "spacing/spacing_field.hpp"

#include <algorithm>
#include <exception>
#include <thread>

namespace pdmesh {

void SpacingField::at_many(const std::vector<Vec2>& p, std::vector<double>& q) const {
  q.resize(p.size());
  for (std::size_t i = 0; i < p.size(); ++i) q[i] = at(p[i]);
}

void for_chunks(std::size_t n, std::size_t max_threads, const std::function<void(std::size_t, std::size_t)>& body) {
  const std::size_t hardware = std::max(1u, std::thread::hardware_concurrency());
  const std::size_t threads = std::min({hardware, max_threads, (n + kPointsPerThread - 1) / kPointsPerThread});
  if (threads <= 1) {
    body(0, n);
    return;
  }
  std::vector<std::exception_ptr> errors(threads);
  auto run = [&](std::size_t t, std::size_t begin, std::size_t end) {
    try {
      body(begin, end);
    } catch (...) {
      errors[t] = std::current_exception();  // rethrown on the calling thread below
    }
  };
  std::vector<std::thread> workers;
  const std::size_t chunk = (n + threads - 1) / threads;
  for (std::size_t t = 1; t < threads; ++t) workers.emplace_back(run, t, std::min(n, t * chunk), std::min(n, (t + 1) * chunk));
  run(0, 0, std::min(n, chunk));
  for (std::thread& w : workers) w.join();
  for (const std::exception_ptr& e : errors)
    if (e) std::rethrow_exception(e);
}

}  // namespace pdmesh
