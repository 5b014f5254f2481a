// The SpacingField base: the default many-point evaluation, and the thread split of large batches.
#include "spacing/spacing_field.hpp"

#include <algorithm>
#include <thread>

#include "core/parallel.hpp"

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
  // One index per chunk on parallel_for's threads (its pool: no thread created per call); the error
  // of the lowest failing chunk is the one rethrown.
  const std::size_t chunk = (n + threads - 1) / threads;
  parallel_for(
      threads, [&](std::size_t t) { body(std::min(n, t * chunk), std::min(n, (t + 1) * chunk)); }, 1, threads);
}

}  // namespace pdmesh
