// The simulation's progress line; see progress.hpp.
#include "sim/progress.hpp"

#include <fmt/format.h>
#include <unistd.h>

namespace pdmesh {

ProgressLine::ProgressLine(bool quiet, std::FILE* stream)
    : quiet_(quiet),
      stream_(stream),
      start_(Clock::now()),
      last_draw_(start_),
      // A terminal gets one line redrawn in place; a log file gets a new line every few seconds.
      terminal_(isatty(fileno(stream)) != 0) {}

void ProgressLine::update(int iteration, int total, double average_force, double dt_gm) {
  if (quiet_) return;
  const auto now = Clock::now();
  const double elapsed = std::chrono::duration<double>(now - start_).count();
  const bool last = iteration >= total;
  const double interval = terminal_ ? 0.1 : 5.0;
  if (elapsed < 1.0 || (!last && std::chrono::duration<double>(now - last_draw_).count() < interval)) return;
  if (!terminal_ && last && !drawn_) return;  // a short run needs no line in a log
  last_draw_ = now;
  const double remaining = iteration > 0 ? elapsed * (total - iteration) / iteration : 0.0;
  fmt::print(stream_, "{}simulation {}/{}  average |F| {:.4g}  dt_GM {:.4g}  elapsed {:.1f} s  remaining {:.1f} s{}",
             terminal_ ? "\r" : "", iteration, total, average_force, dt_gm, elapsed, remaining, terminal_ ? " " : "\n");
  std::fflush(stream_);
  drawn_ = true;
}

void ProgressLine::finish() {
  if (drawn_ && terminal_) fmt::print(stream_, "\n");
  drawn_ = false;
}

}  // namespace pdmesh
