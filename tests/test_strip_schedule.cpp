// The order of the strips of a sweep (host/cleanup/strip_schedule.hpp): every strip runs once, an odd
// strip never before its even neighbours have returned (so never beside them), on any thread count.
#include <catch2/catch.hpp>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <mutex>
#include <stdexcept>
#include <thread>
#include <vector>

#include "cleanup/strip_schedule.hpp"

using namespace pdmesh;

namespace {

// Runs run_strips over `strips` strips whose runs take a little time each (longer for some, so the
// threads overtake each other), recording each strip's start and end as ticks of one counter.
struct Record {
  std::vector<int> runs, start, end;
  int most_at_once = 0;
};

Record schedule(int strips, std::size_t threads) {
  Record r;
  const auto n = static_cast<std::size_t>(strips);
  r.runs.assign(n, 0);
  r.start.assign(n, -1);
  r.end.assign(n, -1);
  std::vector<std::size_t> work(n);
  for (std::size_t s = 0; s < n; ++s) work[s] = (s * 7) % 5;
  std::mutex mutex;
  int tick = 0, now_running = 0;
  cleanup::run_strips(
      strips, work,
      [&](int s) {
        const auto k = static_cast<std::size_t>(s);
        {
          std::lock_guard<std::mutex> lock(mutex);
          ++r.runs[k];
          r.start[k] = tick++;
          r.most_at_once = std::max(r.most_at_once, ++now_running);
        }
        std::this_thread::sleep_for(std::chrono::microseconds(200 + 300 * ((k * 3) % 4)));
        std::lock_guard<std::mutex> lock(mutex);
        r.end[k] = tick++;
        --now_running;
      },
      threads);
  return r;
}

}  // namespace

TEST_CASE("run_strips runs every strip once, odd strips after their even neighbours", "[cleanup][strips]") {
  for (const int strips : {1, 2, 3, 8, 9, 64}) {
    for (const std::size_t threads : {std::size_t{1}, std::size_t{2}, std::size_t{4}}) {
      INFO("strips " << strips << ", threads " << threads);
      const Record r = schedule(strips, threads);
      for (int s = 0; s < strips; ++s) {
        const auto k = static_cast<std::size_t>(s);
        CHECK(r.runs[k] == 1);
        if (s % 2 == 0) continue;
        CHECK(r.start[k] > r.end[k - 1]);
        if (k + 1 < r.end.size()) CHECK(r.start[k] > r.end[k + 1]);
      }
      CHECK(r.most_at_once <= static_cast<int>(threads));
      if (threads == 1) CHECK(r.most_at_once == 1);
    }
  }
}

TEST_CASE("run_strips overlaps the colours: an odd strip may start before the last even one", "[cleanup][strips]") {
  if (std::thread::hardware_concurrency() < 2) return;  // one worker runs the strips in turn
  // Strip 6 has the most work, so it starts first, and it does not return until an odd strip has
  // started (or 20 s have passed): with 2 threads the other one runs 0, 2 and 4 and then strip 1 or 3,
  // whose even neighbours are done. A barrier between the colours would start no odd strip first.
  const int strips = 8;
  std::vector<std::size_t> work = {1, 0, 1, 0, 1, 0, 9, 0};
  std::mutex mutex;
  std::condition_variable odd_started;
  bool odd = false, odd_before_six_ended = false;
  std::vector<int> order;
  cleanup::run_strips(
      strips, work,
      [&](int s) {
        std::unique_lock<std::mutex> lock(mutex);
        order.push_back(s);
        if (s % 2 == 1) {
          odd = true;
          odd_started.notify_all();
        }
        if (s == 6) odd_before_six_ended = odd_started.wait_for(lock, std::chrono::seconds(20), [&] { return odd; });
      },
      2);
  CHECK(order.front() == 6);
  CHECK(odd_before_six_ended);
  CHECK(order.size() == 8);
}

TEST_CASE("run_strips rethrows a strip's exception and starts no strip after it", "[cleanup][strips]") {
  for (const std::size_t threads : {std::size_t{1}, std::size_t{3}}) {
    std::atomic<int> ran{0};
    std::vector<std::size_t> work(20, 1);
    CHECK_THROWS_AS(cleanup::run_strips(
                        20, work,
                        [&](int s) {
                          ++ran;
                          if (s == 4) throw std::runtime_error("strip 4");
                        },
                        threads),
                    std::runtime_error);
    CHECK(ran.load() < 20);
  }
}
