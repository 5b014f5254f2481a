// The phases of a run (app/pipeline/run_phases): timers and notes in the --timings JSON (well-formed, every
// phase once), pictures drawn on the background thread and waited for, a picture's exception
// surfacing from wait_pictures(), and the same jobs drawn at once without the thread. No timing is
// asserted beyond what the clocks guarantee (non-negative, ordered).
#include <catch2/catch.hpp>

#include <atomic>
#include <chrono>
#include <cmath>
#include <future>
#include <memory>
#include <stdexcept>
#include <string>
#include <thread>

#include "app/pipeline/run_phases.hpp"
#include "core/errors.hpp"
#include "json_check.hpp"

using namespace pdmesh;

namespace {

bool valid_json(const std::string& text) {
  pdmesh_test::JsonCheck check;
  const bool ok = check.valid(text);
  INFO(check.error() << "\n" << text);
  CHECK(ok);
  return ok;
}

std::size_t count(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (auto at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

}  // namespace

TEST_CASE("json check: accepts JSON and refuses what is not", "[phases]") {
  pdmesh_test::JsonCheck c;
  CHECK(c.valid(R"({"a": [1, -2.5e-3, true, null, "x\"\u00e9"], "b": {}})"));
  CHECK_FALSE(c.valid(R"({"a": 1,})"));
  CHECK_FALSE(c.valid(R"({"a": nan})"));
  CHECK_FALSE(c.valid(R"({"a": inf})"));
  CHECK_FALSE(c.valid(R"({"a": 01})"));
  CHECK_FALSE(c.valid(R"({"a": "b)"));
  CHECK_FALSE(c.valid("{\"a\": \"tab\there\"}"));
  CHECK_FALSE(c.valid(R"({"a": 1} {)"));
}

TEST_CASE("run phases: timers, notes and pictures in the timings JSON", "[phases]") {
  RunPhases run;
  { const auto t = run.phase("read"); }
  auto t = run.phase("spacing");
  t.stop();
  t.stop();  // a second stop adds nothing
  t = run.phase("fill");
  t = run.phase("simulation \"host\"");  // assigning ends the running phase ("fill")
  t.stop();
  run.note("iterations", 520);
  run.note("nodes", 2304);
  run.note("iterations", 600);         // a note set twice keeps its last value
  run.note("estimate", std::nan(""));  // JSON has no NaN: null
  run.note("backend", std::string("opencl:0:0"));
  run.note("backend", std::string("the \"host\" reference"));  // a text note set twice keeps its last value
  std::atomic<int> drawn{0};
  run.picture("a.png", [&] { ++drawn; });
  run.picture("b.png", [&] { ++drawn; });
  run.wait_pictures();
  CHECK(drawn == 2);
  const std::vector<PhaseTime> phases = run.phases();
  REQUIRE(phases.size() == 6);
  CHECK(phases[0].name == "read");
  CHECK(phases[1].name == "spacing");
  CHECK(phases[2].name == "fill");
  CHECK(phases[3].name == "simulation \"host\"");
  for (const PhaseTime& p : phases) {
    INFO(p.name);
    CHECK(p.wall >= 0.0);
    CHECK(p.cpu >= 0.0);
    CHECK(p.background == (p.name.size() > 4 && p.name.substr(p.name.size() - 4) == ".png"));
  }
  CHECK(run.elapsed() >= 0.0);
  const std::string json = run.json();
  REQUIRE(valid_json(json));
  CHECK(count(json, "\"name\": \"read\"") == 1);
  CHECK(count(json, "\"name\": \"simulation \\\"host\\\"\"") == 1);  // escaped
  CHECK(count(json, "\"background\": true") == 2);
  CHECK(count(json, "\"iterations\": 600,") == 1);
  CHECK(count(json, "\"nodes\": 2304,") == 1);
  CHECK(count(json, "\"estimate\": null,") == 1);
  CHECK(count(json, "\"backend\": \"the \\\"host\\\" reference\",") == 1);  // escaped
  CHECK(count(json, "opencl:0:0") == 0);
  CHECK(count(json, "\"peak_rss_bytes\": ") == 1);
  CHECK(count(json, "\"format\": \"pdmesh-timings\"") == 1);
  const std::string line = run.summary();
  CHECK(line.find("read ") != std::string::npos);
  CHECK(line.find("2 picture(s)") != std::string::npos);
  CHECK(line.find("on a background thread") != std::string::npos);
}

TEST_CASE("run phases: a run without phases or pictures still writes valid JSON", "[phases]") {
  const RunPhases run;
  const std::string json = run.json();
  REQUIRE(valid_json(json));
  CHECK(count(json, "\"phases\": [\n  ]") == 1);
  CHECK(run.summary().find("picture") == std::string::npos);
}

TEST_CASE("run phases: pictures run on the background thread while the caller goes on", "[phases]") {
  RunPhases run;
  std::promise<void> release;
  std::shared_future<void> released = release.get_future().share();
  std::atomic<bool> first_done{false}, second_done{false};
  std::thread::id caller = std::this_thread::get_id(), drawer;
  std::promise<void> started;
  // The first job waits until the caller releases it: picture() must have returned without it, and
  // the background thread has started it while the caller was not waiting.
  run.picture("slow.png", [&] {
    drawer = std::this_thread::get_id();
    started.set_value();
    released.wait();
    first_done = true;
  });
  run.picture("next.png", [&] { second_done = true; });
  started.get_future().wait();
  CHECK_FALSE(first_done);
  { const auto t = run.phase("work meanwhile"); }
  release.set_value();
  run.wait_pictures();
  CHECK(first_done);
  CHECK(second_done);
  CHECK(drawer != caller);
  // Queued after a wait: the thread takes them too.
  bool third = false;
  run.picture("third.png", [&] { third = true; });
  run.wait_pictures();
  CHECK(third);
  std::size_t background = 0;
  for (const PhaseTime& p : run.phases()) background += p.background ? 1 : 0;
  CHECK(background == 3);
}

TEST_CASE("run phases: held pictures wait until released, a deadline, wait_pictures or the end", "[phases]") {
  SECTION("release: the background thread draws them") {
    RunPhases run;
    std::atomic<bool> drawn{false};
    std::promise<std::thread::id> drawer;
    PictureHold hold(run, true);
    run.picture("held.png", [&] {
      drawn = true;
      drawer.set_value(std::this_thread::get_id());
    });
    // Held: the thread, idle otherwise, starts nothing (without the hold it would have by now).
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    CHECK_FALSE(drawn);
    hold.release();
    CHECK(drawer.get_future().get() != std::this_thread::get_id());
    run.wait_pictures();
    CHECK(drawn);
  }
  SECTION("wait_pictures draws held pictures") {
    RunPhases run;
    bool drawn = false;
    const PictureHold hold(run, true);
    run.picture("held.png", [&] { drawn = true; });
    run.wait_pictures();
    CHECK(drawn);
  }
  SECTION("pictures still held when the run ends are drawn") {
    std::atomic<int> drawn{0};
    {
      RunPhases run;
      run.hold_pictures(true);
      run.picture("a.png", [&] { ++drawn; });
      run.picture("b.png", [&] { ++drawn; });
    }
    CHECK(drawn == 2);
  }
  SECTION("a hold ends at its deadline") {
    RunPhases run;
    std::promise<void> done;
    const PictureHold hold(run, true, 0.05);
    run.picture("late.png", [&] { done.set_value(); });
    done.get_future().wait();  // drawn by the thread once 0.05 s have passed, the hold object alive
    run.wait_pictures();
  }
  SECTION("an inactive hold holds nothing") {
    RunPhases run;
    std::promise<void> done;
    const PictureHold hold(run, false);
    run.picture("free.png", [&] { done.set_value(); });
    done.get_future().wait();  // drawn by the thread while the hold object lives
    run.wait_pictures();
  }
}

TEST_CASE("run phases: a caller waiting for the pictures draws queued ones itself", "[phases]") {
  RunPhases run;
  // Whichever thread takes the first job blocks in it until the second job runs, which only the other
  // thread can do: the two run on different threads, one of them the waiting caller.
  std::promise<void> release;
  std::shared_future<void> released = release.get_future().share();
  std::thread::id first, second;
  run.picture("blocked.png", [&] {
    first = std::this_thread::get_id();
    released.wait();
  });
  run.picture("releases.png", [&] {
    second = std::this_thread::get_id();
    release.set_value();
  });
  run.wait_pictures();
  CHECK(first != second);
  CHECK((first == std::this_thread::get_id() || second == std::this_thread::get_id()));
  for (const PhaseTime& p : run.phases()) CHECK(p.background);
}

TEST_CASE("run phases: a picture's exception surfaces from wait_pictures, once, and the others are drawn", "[phases]") {
  RunPhases run;
  bool after = false;
  run.picture("bad.png", [] { throw InputError("cannot write 'bad.png'"); });
  run.picture("second bad.png", [] { throw std::runtime_error("not the first"); });
  run.picture("good.png", [&] { after = true; });
  CHECK_THROWS_AS(run.wait_pictures(), InputError);
  CHECK(after);
  CHECK_NOTHROW(run.wait_pictures());  // reported once: the first error only
  CHECK(run.phases().size() == 3);     // every job was timed, failed or not
}

TEST_CASE("run phases: without the thread a picture is drawn at once and its error is thrown there", "[phases]") {
  RunPhases run(false);
  std::thread::id drawer;
  run.picture("now.png", [&] { drawer = std::this_thread::get_id(); });
  CHECK(drawer == std::this_thread::get_id());
  REQUIRE(run.phases().size() == 1);
  CHECK_FALSE(run.phases()[0].background);
  CHECK_THROWS_AS(run.picture("bad.png", [] { throw InputError("bad"); }), InputError);
  CHECK_NOTHROW(run.wait_pictures());
}

TEST_CASE("run phases: the guard waits for the pictures when an exception unwinds, without throwing", "[phases]") {
  RunPhases run;
  std::atomic<bool> drawn{false};
  try {
    const PictureGuard guard(run);
    run.picture("late.png", [&] {
      std::this_thread::yield();
      drawn = true;
    });
    run.picture("failing.png", [] { throw InputError("lost under the unwinding error"); });
    throw std::runtime_error("the run failed");
  } catch (const std::runtime_error& e) {
    CHECK(std::string(e.what()) == "the run failed");
  }
  CHECK(drawn);  // the guard waited before the data the job reads went away
}

// The pipeline lets a queued picture own what it draws (the initial distribution): that must go when
// the picture is done, not when the run waits for its pictures at its end.
TEST_CASE("run phases: a drawn picture's captures are released before the next picture runs", "[phases]") {
  RunPhases run;
  auto data = std::make_shared<std::vector<int>>(1000, 7);
  const std::weak_ptr<std::vector<int>> watch = data;
  std::promise<bool> first_saw, released;
  run.picture("first.png", [data, &first_saw] { first_saw.set_value(data->at(999) == 7); });
  data.reset();
  // One background thread draws the queue in order: this job runs after the first one has ended.
  run.picture("second.png", [watch, &released] { released.set_value(watch.expired()); });
  CHECK(first_saw.get_future().get());
  CHECK(released.get_future().get());
  run.wait_pictures();
}
