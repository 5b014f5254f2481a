// Progress notes of long phases (building the spacing field, refining, cleaning up, writing): a line
// on the process's progress sink (stderr for the command unless --quiet; none by default, as in the
// library and the Python API), at most one every kProgressInterval seconds per phase and none in
// the phase's first seconds, so that a short run prints what it always printed and a big one never
// sits silent for minutes.
#pragma once
#include <chrono>
#include <condition_variable>
#include <functional>
#include <mutex>
#include <string>
#include <thread>
#include <utility>

namespace pdmesh {

inline constexpr double kProgressInterval = 5.0;

using ProgressSink = std::function<void(const std::string& line)>;

// Sets the process's sink (empty: none). Not thread-safe: set it before the work starts.
void set_progress_sink(ProgressSink sink);
bool has_progress_sink();
// One line on the sink, at once (for a phase's start when it will be long).
void progress_line(const std::string& line);

// The phase running now, for the heartbeat: RunPhases' timers set it when a phase starts and clear it
// (when it is still theirs) when it ends. Thread-safe.
void set_current_phase(const std::string& name);
void clear_current_phase(const std::string& name);

// While alive: when the current phase has run for kProgressInterval seconds with no progress line,
// prints "<phase>: still running (N s)" on the sink, then again after twice the last wait, at most
// kHeartbeatMaxInterval (5, 10, 20, 40, 60, 60, ... s), so that a long phase says it is alive without
// a line every few seconds. The simulation is left alone (its own progress line is drawn in place).
inline constexpr double kHeartbeatMaxInterval = 60.0;
class ProgressHeartbeat {
 public:
  ProgressHeartbeat();
  ~ProgressHeartbeat();
  ProgressHeartbeat(const ProgressHeartbeat&) = delete;
  ProgressHeartbeat& operator=(const ProgressHeartbeat&) = delete;

 private:
  void run();
  std::mutex mutex_;
  std::condition_variable cv_;
  bool stop_ = false;
  std::thread thread_;
};

// A phase's notes: note() prints "<phase>: <text>" when kProgressInterval seconds have passed since
// the phase began or since its last note; `text` is only called then.
class PhaseProgress {
 public:
  explicit PhaseProgress(std::string phase);
  template <class TextFn>
  void note(TextFn&& text) {
    if (!has_progress_sink()) return;
    const auto now = Clock::now();
    if (std::chrono::duration<double>(now - last_).count() < kProgressInterval) return;
    last_ = now;
    progress_line(phase_ + ": " + std::forward<TextFn>(text)() + " (" +
                  std::to_string(static_cast<long>(std::chrono::duration<double>(now - start_).count())) + " s)");
  }

 private:
  using Clock = std::chrono::steady_clock;
  std::string phase_;
  Clock::time_point start_;
  Clock::time_point last_;
};

}  // namespace pdmesh
