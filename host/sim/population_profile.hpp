// PDMESH_POPULATION_PROFILE=1: the wall seconds of each part of a population event (the plan's
// triangulation and rules, the apply, the device run's read-back, mapping and re-upload), one line per
// event on stderr. A diagnosis only: the parts are timed whether or not it is set (a clock read each),
// and nothing else reads them.
#pragma once
#include <chrono>

namespace pdmesh::population_profile {

// Adds `seconds` to the part named `part` (a string literal) of the current event.
void add(const char* part, double seconds);
// With the variable set: prints the parts recorded since the last print, labelled `when`, and forgets
// them. Without it: forgets them.
void print(const char* when);

// Times its own life into `part`.
class Timer {
 public:
  explicit Timer(const char* part) : part_(part), start_(std::chrono::steady_clock::now()) {}
  ~Timer() { add(part_, std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count()); }
  Timer(const Timer&) = delete;
  Timer& operator=(const Timer&) = delete;

 private:
  const char* part_;
  std::chrono::steady_clock::time_point start_;
};

}  // namespace pdmesh::population_profile
