// Phase timing and the background picture thread; see run_phases.hpp.
#include "app/pipeline/run_phases.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <signal.h>
#include <unistd.h>
#include <fstream>

#include <fmt/format.h>

#include "core/free_memory.hpp"
#include "core/interrupt.hpp"
#include "core/progress_notes.hpp"
#include "io/quality_report.hpp"

namespace pdmesh {
namespace {

// Test hook (docs/robustness.md): PDMESH_TEST_SIGNAL_IN_PHASE=NAME[@SECONDS] sends this process a
// SIGINT when the phase NAME begins (after SECONDS, from a thread, when given), and notes on stderr
// the wall-clock time it did, so that a test or tools/bench/interrupt_latency.sh can stop a run in any
// phase and time how long it takes to end.
void signal_in_phase(const std::string& name) {
  static const char* const spec = std::getenv("PDMESH_TEST_SIGNAL_IN_PHASE");
  if (spec == nullptr) return;
  const std::string text(spec);
  const auto at = text.find('@');
  if (text.substr(0, at) != name) return;
  const double delay = at == std::string::npos ? 0.0 : std::atof(text.c_str() + at + 1);
  const auto send = [delay] {
    if (delay > 0.0) std::this_thread::sleep_for(std::chrono::duration<double>(delay));
    timespec ts{};
    clock_gettime(CLOCK_REALTIME, &ts);
    std::fprintf(stderr, "pdmesh: test: SIGINT sent at %lld.%09ld\n", static_cast<long long>(ts.tv_sec), ts.tv_nsec);
    std::fflush(stderr);
    ::kill(::getpid(), SIGINT);
  };
  if (delay > 0.0) {
    std::thread(send).detach();
  } else {
    send();
  }
}

}  // namespace

double wall_seconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

std::size_t peak_rss_bytes() {
  std::ifstream f("/proc/self/status");
  std::string key;
  while (f >> key) {
    if (key == "VmHWM:") {
      std::size_t kb = 0;
      f >> kb;
      return kb * 1024;
    }
    std::getline(f, key);
  }
  return 0;
}

RunPhases::RunPhases(bool background)
    : background_(background), start_wall_(wall_seconds()), start_cpu_(process_cpu_seconds()) {}

RunPhases::~RunPhases() {
  {
    std::unique_lock lock(mutex_);
    held_ = false;
    cv_.notify_all();
    cv_.wait(lock, [this] { return pending_ == 0; });
    stopping_ = true;
  }
  cv_.notify_all();
  if (thread_.joinable()) thread_.join();
}

RunPhases::Timer::Timer(RunPhases& phases, std::string name)
    : phases_(&phases), name_(std::move(name)), wall0_(wall_seconds()), cpu0_(process_cpu_seconds()) {
  // Each phase begins without the free pages of the phases before it, so that its peak does not carry
  // what they freed (tools/bench/rss_trace.py).
  give_back_free_memory();
  set_current_phase(name_);  // for the progress heartbeat (core/progress_notes.hpp)
  {
    std::lock_guard lock(phases.mutex_);
    phases.current_ = name_;
  }
  signal_in_phase(name_);
}

RunPhases::Timer::Timer(Timer&& other) noexcept
    : phases_(other.phases_), name_(std::move(other.name_)), wall0_(other.wall0_), cpu0_(other.cpu0_) {
  other.phases_ = nullptr;
}

RunPhases::Timer& RunPhases::Timer::operator=(Timer&& other) noexcept {
  if (this != &other) {
    stop();
    phases_ = other.phases_;
    name_ = std::move(other.name_);
    wall0_ = other.wall0_;
    cpu0_ = other.cpu0_;
    other.phases_ = nullptr;
  }
  return *this;
}

void RunPhases::Timer::stop() {
  if (!phases_) return;
  phases_->add({name_, wall_seconds() - wall0_, process_cpu_seconds() - cpu0_, false});
  clear_current_phase(name_);
  phases_ = nullptr;
}

void RunPhases::add(PhaseTime t) {
  std::lock_guard lock(mutex_);
  phases_.push_back(std::move(t));
}

namespace {

// Sets key's value in a list of (key, value) facts kept in the order they were first set.
template <class T>
void set_fact(std::vector<std::pair<std::string, T>>& facts, const std::string& key, T value) {
  for (auto& [k, v] : facts) {
    if (k == key) {
      v = std::move(value);
      return;
    }
  }
  facts.emplace_back(key, std::move(value));
}

}  // namespace

void RunPhases::note(const std::string& key, const std::string& value) {
  std::lock_guard lock(mutex_);
  set_fact(text_notes_, key, value);
}

void RunPhases::note(const std::string& key, double value) {
  std::lock_guard lock(mutex_);
  set_fact(notes_, key, value);
}

void RunPhases::picture(std::string name, std::function<void()> job) {
  if (!background_) {
    const double w0 = wall_seconds(), c0 = thread_cpu_seconds();
    job();
    add({std::move(name), wall_seconds() - w0, thread_cpu_seconds() - c0, false});
    return;
  }
  {
    std::lock_guard lock(mutex_);
    queue_.push_back(Job{next_seq_++, std::move(name), std::move(job)});
    ++pending_;
    if (!thread_.joinable()) thread_ = std::thread(&RunPhases::worker, this);
  }
  cv_.notify_all();
}

void RunPhases::hold_pictures(bool hold, double max_seconds) {
  {
    std::lock_guard lock(mutex_);
    held_ = hold;
    if (hold)
      held_until_ = std::chrono::steady_clock::now() + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                                           std::chrono::duration<double>(std::min(max_seconds, 1e6)));
  }
  cv_.notify_all();
}

void RunPhases::worker() {
  std::unique_lock lock(mutex_);
  for (;;) {
    const auto ready = [this] { return stopping_ || (!queue_.empty() && !held_); };
    if (held_) {
      // A hold lasts until released or until its deadline, whichever comes first.
      if (!cv_.wait_until(lock, held_until_, ready)) held_ = false;
    } else {
      cv_.wait(lock, ready);
    }
    if (!ready()) continue;
    if (queue_.empty()) return;  // stopping, nothing left
    run_job(lock);
  }
}

void RunPhases::run_job(std::unique_lock<std::mutex>& lock) {
  Job next = std::move(queue_.front());
  queue_.pop_front();
  if (interrupt_flag().load()) {  // stopping: the pictures not begun are abandoned
    --pending_;
    cv_.notify_all();
    return;
  }
  lock.unlock();
  const double w0 = wall_seconds(), c0 = thread_cpu_seconds();
  std::exception_ptr error;
  try {
    next.job();
  } catch (...) {
    error = std::current_exception();
  }
  const PhaseTime t{std::move(next.name), wall_seconds() - w0, thread_cpu_seconds() - c0, true};
  lock.lock();
  phases_.push_back(t);
  if (error && (!error_ || next.seq < error_seq_)) {
    error_ = error;
    error_seq_ = next.seq;
  }
  --pending_;
  cv_.notify_all();
}

void RunPhases::wait_pictures() {
  std::exception_ptr error;
  {
    std::unique_lock lock(mutex_);
    held_ = false;
    cv_.notify_all();
    // The caller has nothing else to do: it draws queued pictures too, beside the background thread
    // (30P30N's six mesh pictures, drawn at the end of a run, were its wait).
    while (!queue_.empty()) run_job(lock);
    cv_.wait(lock, [this] { return pending_ == 0; });
    std::swap(error, error_);
  }
  if (error) std::rethrow_exception(error);
}

PictureGuard::~PictureGuard() {
  try {
    phases_.wait_pictures();
  } catch (...) {  // not reported over the exception that is unwinding
  }
}

std::string RunPhases::current_phase() const {
  std::lock_guard lock(mutex_);
  return current_;
}

std::vector<PhaseTime> RunPhases::phases() const {
  std::lock_guard lock(mutex_);
  return phases_;
}

double RunPhases::elapsed() const { return wall_seconds() - start_wall_; }

std::string RunPhases::summary() const {
  const std::vector<PhaseTime> all = phases();
  std::string line;
  double pictures = 0.0;
  std::size_t count = 0;
  for (const PhaseTime& p : all) {
    if (p.background) {
      pictures += p.wall;
      ++count;
      continue;
    }
    line += fmt::format("{}{} {:.3f}", line.empty() ? "" : ", ", p.name, p.wall);
  }
  if (count > 0) line += fmt::format("; {} picture(s) {:.3f} on a background thread", count, pictures);
  return fmt::format("timing (wall s): {}; whole run {:.3f} s wall, {:.3f} s CPU", line, elapsed(),
                     process_cpu_seconds() - start_cpu_);
}

std::string RunPhases::json() const {
  const std::vector<PhaseTime> all = phases();
  std::string out = "{\n  \"format\": \"pdmesh-timings\",\n  \"version\": 1,\n";
  out += fmt::format("  \"wall\": {:.6f},\n  \"cpu\": {:.6f},\n  \"peak_rss_bytes\": {},\n", elapsed(),
                     process_cpu_seconds() - start_cpu_, peak_rss_bytes());
  {
    std::lock_guard lock(mutex_);
    // JSON has no NaN or infinity: such a fact is null.
    for (const auto& [k, v] : notes_)
      out += fmt::format("  {}: {},\n", json_string(k), std::isfinite(v) ? fmt::format("{}", v) : std::string("null"));
    for (const auto& [k, v] : text_notes_) out += fmt::format("  {}: {},\n", json_string(k), json_string(v));
  }
  out += "  \"phases\": [\n";
  for (std::size_t i = 0; i < all.size(); ++i) {
    const PhaseTime& p = all[i];
    out +=
        fmt::format("    {{\"name\": {}, \"wall\": {:.6f}, \"cpu\": {:.6f}, \"background\": {}}}{}\n",
                    json_string(p.name), p.wall, p.cpu, p.background ? "true" : "false", i + 1 < all.size() ? "," : "");
  }
  out += "  ]\n}\n";
  return out;
}

}  // namespace pdmesh
