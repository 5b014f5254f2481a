// The process's progress sink; see progress_notes.hpp.
#include "core/progress_notes.hpp"

#include <algorithm>
#include <mutex>

namespace pdmesh {

namespace {
ProgressSink& sink() {
  static ProgressSink s;
  return s;
}
// Notes may come from several threads (a picture on the background thread, a stage on the main one,
// the heartbeat): this also guards the current phase and the time of the last line.
std::mutex& sink_mutex() {
  static std::mutex m;
  return m;
}
using Clock = std::chrono::steady_clock;
struct State {
  std::string phase;
  Clock::time_point phase_start{};
  Clock::time_point last_line{};
};
State& state() {
  static State s;
  return s;
}
}  // namespace

void set_progress_sink(ProgressSink s) { sink() = std::move(s); }

bool has_progress_sink() { return static_cast<bool>(sink()); }

void progress_line(const std::string& line) {
  if (!sink()) return;
  const std::lock_guard<std::mutex> lock(sink_mutex());
  sink()(line);
  state().last_line = Clock::now();
}

void set_current_phase(const std::string& name) {
  const std::lock_guard<std::mutex> lock(sink_mutex());
  state().phase = name;
  state().phase_start = Clock::now();
}

void clear_current_phase(const std::string& name) {
  const std::lock_guard<std::mutex> lock(sink_mutex());
  if (state().phase == name) state().phase.clear();
}

ProgressHeartbeat::ProgressHeartbeat() : thread_([this] { run(); }) {}

ProgressHeartbeat::~ProgressHeartbeat() {
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  cv_.notify_all();
  thread_.join();
}

void ProgressHeartbeat::run() {
  std::unique_lock<std::mutex> lock(mutex_);
  std::string phase;        // the phase the wait below is for
  Clock::time_point start;  // its start
  double wait = kProgressInterval;
  while (!cv_.wait_for(lock, std::chrono::seconds(1), [this] { return stop_; })) {
    const std::lock_guard<std::mutex> sink_lock(sink_mutex());
    State& st = state();
    if (st.phase != phase || st.phase_start != start) {
      phase = st.phase;
      start = st.phase_start;
      wait = kProgressInterval;
    }
    if (!sink() || phase.empty() || phase == "simulation") continue;
    const auto now = Clock::now();
    const auto since = std::max(st.phase_start, st.last_line);
    if (std::chrono::duration<double>(now - since).count() < wait) continue;
    const double running = std::chrono::duration<double>(now - st.phase_start).count();
    sink()(phase + ": still running (" + std::to_string(static_cast<long>(running)) + " s)");
    st.last_line = now;
    wait = std::min(2.0 * wait, kHeartbeatMaxInterval);
  }
}

PhaseProgress::PhaseProgress(std::string phase) : phase_(std::move(phase)), start_(Clock::now()), last_(start_) {}

}  // namespace pdmesh
