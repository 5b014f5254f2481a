// The one Catch2 main, compiled once and linked into every test executable, and the hook that lets
// tests release process-wide resources (the shared OpenCL context) before main returns.
#define CATCH_CONFIG_MAIN
#include <catch2/catch.hpp>

#include <functional>
#include <vector>

#include "test_run_end.hpp"

namespace pdmesh::test {

std::vector<std::function<void()>>& run_end_hooks() {
  static std::vector<std::function<void()>> hooks;
  return hooks;
}

void on_test_run_end(std::function<void()> release) { run_end_hooks().push_back(std::move(release)); }

namespace {

// OpenCL objects released from static destructors after main would run after the C++ runtime has
// torn down thread-local storage that some implementations still use (Oclgrind aborts there), and
// vendor ICDs may unload first; so the hooks run when the test run ends, latest registered first.
struct ReleaseAtRunEnd : Catch::TestEventListenerBase {
  using TestEventListenerBase::TestEventListenerBase;
  void testRunEnded(const Catch::TestRunStats&) override {
    auto& hooks = run_end_hooks();
    while (!hooks.empty()) {
      auto release = std::move(hooks.back());
      hooks.pop_back();
      release();
    }
  }
};

CATCH_REGISTER_LISTENER(ReleaseAtRunEnd)

}  // namespace
}  // namespace pdmesh::test
