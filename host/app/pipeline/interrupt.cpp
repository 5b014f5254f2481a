// SIGINT/SIGTERM handlers that only store to lock-free atomics (async-signal-safe): the stop flag of
// core/interrupt, which every long loop polls.
#include "app/pipeline/interrupt.hpp"

#include <csignal>

#include "core/interrupt.hpp"

namespace pdmesh {
namespace {

static_assert(std::atomic<int>::is_always_lock_free, "the signal number is set from a signal handler");

std::atomic<int> g_signal{0};
struct sigaction g_previous_int, g_previous_term;

extern "C" void on_stop_signal(int signal) {
  g_signal.store(signal);
  interrupt_flag().store(true);
  // A second signal ends the process at once (sigaction and SIG_DFL are async-signal-safe).
  struct sigaction dfl {};
  dfl.sa_handler = SIG_DFL;
  sigemptyset(&dfl.sa_mask);
  sigaction(signal, &dfl, nullptr);
}

}  // namespace

InterruptGuard::InterruptGuard() {
  interrupt_flag().store(false);
  g_signal.store(0);
  struct sigaction action {};
  action.sa_handler = on_stop_signal;
  sigemptyset(&action.sa_mask);
  action.sa_flags = SA_RESTART;
  sigaction(SIGINT, &action, &g_previous_int);
  sigaction(SIGTERM, &action, &g_previous_term);
}

InterruptGuard::~InterruptGuard() {
  sigaction(SIGINT, &g_previous_int, nullptr);
  sigaction(SIGTERM, &g_previous_term, nullptr);
}

std::atomic<bool>& InterruptGuard::flag() { return interrupt_flag(); }
int InterruptGuard::signal_number() { return g_signal.load(); }

}  // namespace pdmesh
