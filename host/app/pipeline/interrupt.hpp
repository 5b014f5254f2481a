// SIGINT/SIGTERM handling for `pdmesh mesh`: the first signal sets core/interrupt's stop flag, which
// stops the run wherever it is (the simulation after its current iteration, with a checkpoint; every
// other long phase within a fraction of a second, by check_interrupt); a second one ends the process
// the default way.
#pragma once
#include <atomic>

namespace pdmesh {

// Installs the handlers on construction and restores the previous ones on destruction.
class InterruptGuard {
 public:
  InterruptGuard();
  ~InterruptGuard();
  InterruptGuard(const InterruptGuard&) = delete;
  InterruptGuard& operator=(const InterruptGuard&) = delete;

  // core/interrupt's flag: set by the handler (and by tests or --stop-after).
  static std::atomic<bool>& flag();
  // The signal that set the flag, 0 if none.
  static int signal_number();
};

}  // namespace pdmesh
