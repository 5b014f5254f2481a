// The phases of one `pdmesh mesh` run: each timed (wall and process CPU time) for the progress
// messages, `--timings FILE` and `pdmesh bench --whole-run`; and the pictures, drawn on a background
// thread while the run goes on (docs/performance.md, "How to measure").
#pragma once
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstddef>
#include <deque>
#include <cstdint>
#include <exception>
#include <filesystem>
#include <functional>
#include <mutex>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "core/cpu_time.hpp"  // process_cpu_seconds, thread_cpu_seconds: the phases' CPU times

namespace pdmesh {

struct PhaseTime {
  std::string name;
  double wall = 0.0;  // seconds
  // Process CPU seconds (every thread, background pictures included) during the phase; for a
  // background job, the CPU seconds of the thread that drew it.
  double cpu = 0.0;
  // A picture job, drawn by the background thread (overlapping other phases) or by the caller of
  // RunPhases::wait_pictures while it waits.
  bool background = false;
};

class RunPhases {
 public:
  // background false: pictures are drawn at once, on the calling thread (still timed).
  explicit RunPhases(bool background = true);
  // Waits for the pictures still queued (their errors are dropped: wait_pictures() reports them).
  ~RunPhases();
  RunPhases(const RunPhases&) = delete;
  RunPhases& operator=(const RunPhases&) = delete;

  // Times the enclosing scope as one phase (added when the timer is destroyed or stopped).
  class Timer {
   public:
    Timer(RunPhases& phases, std::string name);
    ~Timer() { stop(); }
    Timer(Timer&& other) noexcept;
    // Ends this phase (if running) and takes over the other's.
    Timer& operator=(Timer&& other) noexcept;
    void stop();

   private:
    RunPhases* phases_;
    std::string name_;
    double wall0_, cpu0_;
  };
  Timer phase(std::string name) { return Timer(*this, std::move(name)); }

  // Draws a picture: queued for the background thread (or drawn now). Whatever the job reads must
  // stay alive and unchanged until wait_pictures() returns.
  void picture(std::string name, std::function<void()> job);
  // Waits for every picture queued so far, drawing queued ones on the calling thread meanwhile;
  // rethrows the error of the earliest queued job that threw (once; queue order, not completion order,
  // so the same error whichever thread drew which picture).
  void wait_pictures();
  // A stop request (core/interrupt) abandons the pictures not begun yet; one being drawn ends with
  // Interrupted (the drawing loops poll it), which wait_pictures() rethrows.
  // While held, queued pictures wait (the background thread starts none), for at most max_seconds;
  // wait_pictures() and the destructor release them.
  void hold_pictures(bool hold, double max_seconds = HUGE_VAL);

  // Adds a phase measured elsewhere; thread-safe.
  void add(PhaseTime t);
  // A fact about the run for the timings file (iterations, nodes, triangles, ...).
  void note(const std::string& key, double value);
  // A fact in words (the backend that ran the simulation): a string in the timings file, so that a
  // run `--device auto` moved to the host reference says so even under -q.
  void note(const std::string& key, const std::string& value);

  std::vector<PhaseTime> phases() const;
  // The name of the phase begun last (by phase()), "" before the first: where a stop came.
  std::string current_phase() const;
  double elapsed() const;  // wall seconds since construction
  // One progress line: the phases in order with their wall times, the pictures' total, the whole.
  std::string summary() const;
  // The JSON of --timings: every phase, the facts, the totals and the peak resident set.
  std::string json() const;

 private:
  void worker();
  // Runs the queue's first job with `lock` (held on entry and on return) released meanwhile; records
  // its time and its error.
  void run_job(std::unique_lock<std::mutex>& lock);
  const bool background_;
  const double start_wall_, start_cpu_;
  mutable std::mutex mutex_;
  std::vector<PhaseTime> phases_;
  std::vector<std::pair<std::string, double>> notes_;
  std::vector<std::pair<std::string, std::string>> text_notes_;
  std::string current_;
  // The background thread and its queue (started with the first picture).
  std::condition_variable cv_;
  struct Job {
    std::uint64_t seq;  // queue order
    std::string name;
    std::function<void()> job;
  };
  std::deque<Job> queue_;
  std::uint64_t next_seq_ = 0;
  std::size_t pending_ = 0;  // queued or running
  bool stopping_ = false;
  bool held_ = false;
  std::chrono::steady_clock::time_point held_until_{};
  std::exception_ptr error_;
  std::uint64_t error_seq_ = 0;  // the queue position of error_'s job
  std::thread thread_;
};

// Waits for the pictures of `phases` when it goes out of scope, errors dropped: declared after the
// data the pictures read, it keeps them from reading freed memory while an exception unwinds.
class PictureGuard {
 public:
  explicit PictureGuard(RunPhases& phases) : phases_(phases) {}
  ~PictureGuard();
  PictureGuard(const PictureGuard&) = delete;
  PictureGuard& operator=(const PictureGuard&) = delete;

 private:
  RunPhases& phases_;
};

// Holds the pictures of `phases` (RunPhases::hold_pictures) from construction, when `active`, until
// release(), destruction or max_seconds.
class PictureHold {
 public:
  PictureHold(RunPhases& phases, bool active, double max_seconds = HUGE_VAL) : phases_(active ? &phases : nullptr) {
    if (phases_) phases_->hold_pictures(true, max_seconds);
  }
  ~PictureHold() { release(); }
  void release() const {
    if (phases_) phases_->hold_pictures(false);
  }
  PictureHold(const PictureHold&) = delete;
  PictureHold& operator=(const PictureHold&) = delete;

 private:
  RunPhases* phases_;
};

// Wall seconds on a steady clock (for phases timed by hand).
double wall_seconds();

// Peak resident set of this process (VmHWM), bytes; 0 where /proc is missing.
std::size_t peak_rss_bytes();

}  // namespace pdmesh
