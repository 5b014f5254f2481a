// SIGINT/SIGTERM handling for `pdmesh mesh`: the first signal asks the run to stop after the current
// iteration (and write a checkpoint); a second one ends the process the default way.
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

  // Set by the handler (and by tests or --stop-after); read by the simulation once per iteration.
  static std::atomic<bool>& flag();
  // The signal that set the flag, 0 if none.
  static int signal_number();
};

}  // namespace pdmesh
