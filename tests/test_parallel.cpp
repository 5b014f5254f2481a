// parallel_for (core/parallel.hpp): every index once whatever the thread count and block size, small
// ranges on the calling thread, and the lowest failing block's exception rethrown.
#include <catch2/catch.hpp>

#include <atomic>
#include <cstdio>
#include <mutex>
#include <set>
#include <sys/syscall.h>
#include <sys/wait.h>
#include <unistd.h>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "core/parallel.hpp"
#include "core/worker_pool.hpp"

using pdmesh::parallel_for;

TEST_CASE("parallel_for runs every index exactly once", "[core][parallel]") {
  for (const std::size_t n : {0u, 1u, 7u, 511u, 512u, 1023u, 10000u, 100003u}) {
    for (const std::size_t min_chunk : {1u, 64u, 512u, 4096u}) {
      std::vector<std::atomic<int>> seen(n);
      parallel_for(
          n, [&](std::size_t i) { seen[i].fetch_add(1); }, min_chunk);
      std::size_t wrong = 0;
      for (const auto& s : seen) wrong += s.load() == 1 ? 0 : 1;
      INFO("n = " << n << ", min_chunk = " << min_chunk);
      CHECK(wrong == 0);
    }
  }
}

TEST_CASE("parallel_for keeps a range of one chunk on the calling thread", "[core][parallel]") {
  const std::thread::id caller = std::this_thread::get_id();
  std::atomic<int> elsewhere{0};
  parallel_for(
      4096, [&](std::size_t) { elsewhere += std::this_thread::get_id() == caller ? 0 : 1; }, 4096);
  CHECK(elsewhere.load() == 0);
}

TEST_CASE("parallel_for rethrows the exception of the lowest failing block", "[core][parallel]") {
  // Every index from 1000 on throws its own index: whichever thread reaches a failing block first,
  // the error rethrown is that of the lowest block that threw, which holds index 1000 whenever the
  // blocks are taken in increasing order by the first thread to fail (the counter only increases).
  const std::size_t n = 100000;
  std::string what;
  try {
    parallel_for(
        n,
        [&](std::size_t i) {
          if (i >= 1000) throw std::runtime_error(std::to_string(i));
        },
        64);
  } catch (const std::runtime_error& e) {
    what = e.what();
  }
  REQUIRE_FALSE(what.empty());
  // The thrower of the lowest block threw at that block's first failing index: 1000 is in the block
  // taken first among the failing ones, so no block below it can have thrown.
  CHECK(what == "1000");
}

namespace {
// A scratch that counts how many are alive and remembers the one thread that may use it.
struct CountedScratch {
  static inline std::atomic<int> alive{0};
  std::thread::id owner{};
  std::vector<std::size_t> seen;
  CountedScratch() { alive.fetch_add(1); }
  CountedScratch(const CountedScratch&) = delete;
  CountedScratch& operator=(const CountedScratch&) = delete;
  ~CountedScratch() { alive.fetch_sub(1); }
};
}  // namespace

TEST_CASE("parallel_for_scratch gives every thread its own scratch and frees it", "[core][parallel]") {
  for (const std::size_t n : {0u, 100u, 100003u}) {
    std::vector<std::atomic<int>> seen(n);
    std::atomic<int> foreign{0};
    pdmesh::parallel_for_scratch<CountedScratch>(
        n,
        [&](CountedScratch& s, std::size_t i) {
          if (s.owner == std::thread::id{}) s.owner = std::this_thread::get_id();
          if (s.owner != std::this_thread::get_id()) foreign.fetch_add(1);
          // The scratch keeps what this thread's earlier indices left: they were taken in rising order.
          if (!s.seen.empty() && s.seen.back() >= i) foreign.fetch_add(1);
          s.seen.push_back(i);
          seen[i].fetch_add(1);
        },
        64);
    CHECK(foreign.load() == 0);
    std::size_t wrong = 0;
    for (const auto& c : seen) wrong += c.load() != 1;
    CHECK(wrong == 0);
    CHECK(CountedScratch::alive.load() == 0);
  }
}

TEST_CASE("WorkerPool runs job(0) on the caller and 1..count on its helpers, one call at a time", "[core][parallel]") {
  pdmesh::WorkerPool pool(3);
  REQUIRE(pool.helpers() == 3);
  for (std::size_t count = 0; count <= 3; ++count) {
    std::vector<std::atomic<int>> ran(4);
    std::vector<std::thread::id> who(4);
    REQUIRE(pool.run(count, [&](std::size_t t) {
      ran[t].fetch_add(1);
      who[t] = std::this_thread::get_id();
    }));
    INFO("count " << count);
    for (std::size_t t = 0; t < 4; ++t) CHECK(ran[t].load() == (t <= count ? 1 : 0));
    CHECK(who[0] == std::this_thread::get_id());
    for (std::size_t t = 1; t <= count; ++t) CHECK(who[t] != std::this_thread::get_id());
  }
  CHECK_FALSE(pool.run(4, [](std::size_t) {}));  // more than it has: the caller makes its own threads
  // A call from inside a job (or from another thread meanwhile) finds the pool busy.
  std::atomic<int> nested_refused{0};
  REQUIRE(pool.run(1, [&](std::size_t t) {
    if (t == 0 && !pool.run(1, [](std::size_t) {})) nested_refused.fetch_add(1);
  }));
  CHECK(nested_refused.load() == 1);
}

TEST_CASE("parallel_for nested in parallel_for runs every index once", "[core][parallel]") {
  const std::size_t outer = 64, inner = 5000;
  std::vector<std::atomic<int>> seen(outer * inner);
  parallel_for(
      outer,
      [&](std::size_t i) {
        parallel_for(
            inner, [&](std::size_t j) { seen[i * inner + j].fetch_add(1); }, 512);
      },
      1);
  std::size_t wrong = 0;
  for (const auto& c : seen) wrong += c.load() != 1;
  CHECK(wrong == 0);
}

TEST_CASE("parallel_for reuses the pool's threads: no thread is created per call", "[core][parallel]") {
  // A thread created while the OpenCL backend's dlopen runs waits for it (core/worker_pool.hpp), so
  // the spacing phase's loops must not create any. Linux thread ids are not reused soon, so threads
  // made per call would show as new ids in every call.
  pdmesh::start_workers();
  std::mutex mutex;
  std::set<long> tids;
  for (int call = 0; call < 20; ++call) {
    parallel_for(
        100000,
        [&](std::size_t) {
          thread_local const long tid = static_cast<long>(syscall(SYS_gettid));  // trivially destructible
          const std::lock_guard<std::mutex> lock(mutex);
          tids.insert(tid);
        },
        512);
  }
  CHECK(tids.size() <= 1 + pdmesh::WorkerPool::instance().helpers());
}

TEST_CASE("parallel_for in a child made by fork() runs on threads of its own", "[core][parallel]") {
  // Python's multiprocessing forks: the child has the pool object but not its helpers.
  pdmesh::start_workers();
  std::fflush(nullptr);
  const pid_t child = fork();
  REQUIRE(child >= 0);
  if (child == 0) {
    std::vector<std::atomic<int>> seen(100000);
    parallel_for(
        seen.size(), [&](std::size_t i) { seen[i].fetch_add(1); }, 512);
    for (const auto& c : seen)
      if (c.load() != 1) _exit(1);
    _exit(0);
  }
  // A child waiting for helpers that do not exist hangs; ctest's timeout then fails this test.
  int status = 0;
  const pid_t done = waitpid(child, &status, 0);
  REQUIRE(done == child);
  CHECK(WIFEXITED(status));
  CHECK(WEXITSTATUS(status) == 0);
}
