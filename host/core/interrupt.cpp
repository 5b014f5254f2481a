// The process-wide stop flag; see interrupt.hpp.
#include "core/interrupt.hpp"

namespace pdmesh {

static_assert(std::atomic<bool>::is_always_lock_free, "the stop flag is set from a signal handler");

namespace {
std::atomic<bool> g_interrupt{false};  // constant-initialized: safe to touch from a signal handler
}  // namespace

std::atomic<bool>& interrupt_flag() { return g_interrupt; }

void throw_interrupted() { throw Interrupted("interrupted"); }

}  // namespace pdmesh
