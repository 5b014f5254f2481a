// Tests of the global maximum time step rule on scripted sequences of maximum force sums.
#include <catch2/catch.hpp>

#include <algorithm>
#include <vector>

#include "sim/global_time_step.hpp"

using namespace pdmesh;

namespace {

// Feeds the sequence and returns the change reported at each step.
std::vector<int> feed(GlobalTimeStep& gm, const std::vector<double>& max_forces) {
  std::vector<int> changes;
  for (double f : max_forces) changes.push_back(gm.update(f));
  return changes;
}

}  // namespace

TEST_CASE("global time step grows after 5 consecutive decreases", "[sim]") {
  GlobalTimeStep gm(0.01);
  // The first value only sets the reference; then 5 decreases.
  const auto changes = feed(gm, {10, 9, 8, 7, 6, 5});
  CHECK(changes == std::vector<int>{0, 0, 0, 0, 0, 1});
  CHECK(gm.dt() == 0.01 * 1.01);
  CHECK(gm.consecutive_decreases() == 0);
  CHECK(gm.increases() == 0);
  // Counters restart: 4 more decreases do nothing, the 5th grows again.
  CHECK(feed(gm, {4, 3, 2, 1}) == std::vector<int>{0, 0, 0, 0});
  CHECK(gm.consecutive_decreases() == 4);
  CHECK(feed(gm, {0.5}) == std::vector<int>{1});
  CHECK(gm.dt() == 0.01 * 1.01 * 1.01);
  CHECK(gm.dt2() == gm.dt() * gm.dt());
}

TEST_CASE("an increase or an equal value breaks the decrease run", "[sim]") {
  GlobalTimeStep gm(1.0);
  feed(gm, {10, 9, 8, 7, 6, 7, 6, 5, 4, 3});  // 4 decreases, increase, 4 decreases
  CHECK(gm.dt() == 1.0);
  CHECK(gm.consecutive_decreases() == 4);
  CHECK(gm.increases() == 1);
  feed(gm, {3});  // equal: breaks the run, not an increase
  CHECK(gm.consecutive_decreases() == 0);
  CHECK(gm.increases() == 1);
  CHECK(gm.dt() == 1.0);
}

TEST_CASE("global time step shrinks after 5 increases before 5 consecutive decreases", "[sim]") {
  GlobalTimeStep gm(1.0);
  // Increases interleaved with short decrease runs: i, d, i, d d, i, d d d, i, d d d d, i.
  const auto changes = feed(gm, {5, 6, 5, 6, 5, 4, 5, 4, 3, 2, 3, 2, 1, 0.5, 0.25, 0.3});
  CHECK(gm.dt() == 0.99);
  CHECK(changes.back() == -1);
  CHECK(std::count(changes.begin(), changes.end(), -1) == 1);
  CHECK(std::count(changes.begin(), changes.end(), 1) == 0);
  CHECK(gm.increases() == 0);
  // Five straight increases shrink again.
  CHECK(feed(gm, {1, 2, 3, 4, 5}) == std::vector<int>{0, 0, 0, 0, -1});
  CHECK(gm.dt() == 0.99 * 0.99);
}

TEST_CASE("a completed decrease run forgets earlier increases", "[sim]") {
  GlobalTimeStep gm(1.0);
  feed(gm, {1, 2, 3, 4, 5});  // 4 increases
  CHECK(gm.increases() == 4);
  feed(gm, {4, 3, 2, 1, 0});  // 5 decreases: grow, reset
  CHECK(gm.dt() == 1.01);
  CHECK(gm.increases() == 0);
  CHECK(feed(gm, {1}) == std::vector<int>{0});  // one increase is not the fifth
  CHECK(gm.dt() == 1.01);
}
