// The global maximum time step rule (thesis ch. 5, "The Global Maximum Time Step"): grow by 1.01
// after the maximum force sum decreases 5 consecutive iterations, shrink by 0.99 when it
// increases 5 times (not necessarily consecutively) before it decreases 5 times consecutively.
#pragma once
#include <optional>

namespace pdmesh {

class GlobalTimeStep {
 public:
  static constexpr int kRunLength = 5;
  static constexpr double kGrow = 1.01;
  static constexpr double kShrink = 0.99;

  // Everything the rule remembers, for checkpoints (restoring it continues bit-identically).
  struct State {
    double dt = 0.0;
    std::optional<double> previous;  // the last max |F| fed; empty before the first
    int consecutive_decreases = 0;
    int increases = 0;
  };

  explicit GlobalTimeStep(double dt_initial) : dt_(dt_initial) {}
  explicit GlobalTimeStep(const State& s)
      : dt_(s.dt), previous_(s.previous), consecutive_decreases_(s.consecutive_decreases), increases_(s.increases) {}
  State state() const { return {dt_, previous_, consecutive_decreases_, increases_}; }

  double dt() const { return dt_; }
  double dt2() const { return dt_ * dt_; }
  // Counters, explicit for tests and the history.
  int consecutive_decreases() const { return consecutive_decreases_; }
  int increases() const { return increases_; }

  // Feeds this iteration's maximum |F|. The first value only sets the reference.
  // A decrease extends the consecutive-decrease run; an increase counts once and breaks the run;
  // an equal value breaks the run and is not an increase. Both counters reset after each change.
  // Returns +1 when dt grew, -1 when it shrank, 0 otherwise.
  int update(double max_force);
  // Multiplies dt by `factor` (SimOptions::metric_anneal), the counters and the last max |F| kept.
  void scale(double factor) { dt_ *= factor; }

 private:
  double dt_;
  std::optional<double> previous_;
  int consecutive_decreases_ = 0;
  int increases_ = 0;
};

}  // namespace pdmesh
