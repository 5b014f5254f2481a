// The simulation's progress line on stderr: shown only once a run has taken more than a second,
// updated in place with \r, finished with one newline.
#pragma once
#include <chrono>
#include <cstdio>

namespace pdmesh {

class ProgressLine {
 public:
  explicit ProgressLine(bool quiet, std::FILE* stream = stderr);
  // Called after each iteration; redraws at most ~10 times a second.
  void update(int iteration, int total, double average_force, double dt_gm);
  // Ends the line (one newline) if anything was drawn.
  void finish();

 private:
  using Clock = std::chrono::steady_clock;
  bool quiet_;
  std::FILE* stream_;
  Clock::time_point start_;
  Clock::time_point last_draw_;
  bool terminal_;
  bool drawn_ = false;
};

}  // namespace pdmesh
