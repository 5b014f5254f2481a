// The stop request of a run (Ctrl-C): a process-wide flag that app/pipeline/interrupt's signal handler sets,
// and a check the long loops of every layer call, which throws Interrupted once it is set. The flag
// lives here, below every layer, so that the geometry, spacing, initialization, triangulation,
// cleanup, writers and pictures can stop within a fraction of a second without knowing about signals.
#pragma once
#include <atomic>

#include "core/errors.hpp"

namespace pdmesh {

// A stop was asked (SIGINT/SIGTERM, or a test's flag): the run unwinds from where it was; main turns
// it into exit status 130. Not an InputError and not a failure.
class Interrupted : public Error {
 public:
  using Error::Error;
};

// The process-wide stop flag (lock-free: set from a signal handler).
std::atomic<bool>& interrupt_flag();

namespace detail {
// InterruptShield's depth on this thread (trivially destructible: no thread-exit registration).
inline thread_local int interrupt_shield_depth = 0;
}  // namespace detail

// While one lives on a thread, check_interrupt() on that thread (and in the parallel_for loops it
// starts) does nothing: for work that must finish once begun so that a consistent state is left
// (a simulation iteration between its first move and its history row; the checkpoint's writing).
class InterruptShield {
 public:
  InterruptShield() { ++detail::interrupt_shield_depth; }
  ~InterruptShield() { --detail::interrupt_shield_depth; }
  InterruptShield(const InterruptShield&) = delete;
  InterruptShield& operator=(const InterruptShield&) = delete;
};
inline bool interrupt_shielded() { return detail::interrupt_shield_depth > 0; }

// Whether a stop has been asked (and this thread is not shielded); a relaxed load, cheap enough for
// every few thousand loop steps.
inline bool interrupt_requested() { return !interrupt_shielded() && interrupt_flag().load(std::memory_order_relaxed); }

// Throws Interrupted when a stop has been asked. Safe on any thread (parallel_for rethrows it on
// the calling thread).
void throw_interrupted();
inline void check_interrupt() {
  if (interrupt_requested()) throw_interrupted();
}

// check_interrupt() at the first and then every `every` calls of tick() (a counter, for loops whose
// steps are very cheap).
class InterruptPoll {
 public:
  explicit InterruptPoll(unsigned every = 4096) : every_(every), count_(every - 1) {}
  void tick() {
    if (++count_ >= every_) {
      count_ = 0;
      check_interrupt();
    }
  }

 private:
  unsigned every_;
  unsigned count_;
};

}  // namespace pdmesh
