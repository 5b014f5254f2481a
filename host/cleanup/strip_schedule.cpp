// The strips of a sweep on the threads, odd strips after their even neighbours (strip_schedule.hpp).
#include "cleanup/strip_schedule.hpp"

#include <algorithm>
#include <condition_variable>
#include <cstdint>
#include <mutex>

#include "core/interrupt.hpp"
#include "core/parallel.hpp"

namespace pdmesh::cleanup {

void run_strips(int strips, const std::vector<std::size_t>& work, const std::function<void(int)>& run,
                std::size_t threads) {
  if (strips <= 0) return;
  const auto n = static_cast<std::size_t>(strips);
  // blockers[s]: the neighbours strip s still waits for (even strips: none).
  std::vector<int> blockers(n, 0);
  for (std::size_t s = 1; s < n; s += 2) blockers[s] = s + 1 < n ? 2 : 1;
  std::vector<std::uint8_t> started(n, 0);
  std::size_t left = n, running = 0;
  bool failed = false;
  std::mutex mutex;
  std::condition_variable changed;
  const bool poll = !interrupt_shielded();
  // The ready strip with the most work, or -1.
  auto pick = [&]() {
    int best = -1;
    for (std::size_t s = 0; s < n; ++s)
      if (!started[s] && blockers[s] == 0 && (best < 0 || work[s] > work[static_cast<std::size_t>(best)]))
        best = static_cast<int>(s);
    return best;
  };
  // Each worker takes ready strips until none is left to start. A worker waits only while another one
  // is running a strip (which may free an odd one), so one worker alone runs them all in turn.
  auto worker = [&](std::size_t) {
    std::unique_lock<std::mutex> lock(mutex);
    while (!failed && left > 0) {
      const int s = pick();
      if (s < 0) {
        changed.wait(lock);
        continue;
      }
      started[static_cast<std::size_t>(s)] = 1;
      --left;
      ++running;
      lock.unlock();
      try {
        if (poll && interrupt_flag().load(std::memory_order_relaxed)) throw_interrupted();
        run(s);
      } catch (...) {
        lock.lock();
        --running;
        failed = true;
        changed.notify_all();
        throw;
      }
      lock.lock();
      --running;
      if (s % 2 == 0) {
        if (s > 0) --blockers[static_cast<std::size_t>(s) - 1];
        if (static_cast<std::size_t>(s) + 1 < n) --blockers[static_cast<std::size_t>(s) + 1];
      }
      changed.notify_all();
    }
  };
  const std::size_t workers = std::min(n, std::max<std::size_t>(1, threads));
  parallel_for(workers, worker, 1, workers);
}

}  // namespace pdmesh::cleanup
