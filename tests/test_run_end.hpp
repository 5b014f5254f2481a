// Releasing process-wide test resources when the Catch2 run ends (tests/catch_main.cpp), before
// static destructors run: the shared OpenCL context and the programs built on it.
#pragma once
#include <functional>

namespace pdmesh::test {

// `release` runs once when the test run ends (hooks in reverse order of registration).
void on_test_run_end(std::function<void()> release);

}  // namespace pdmesh::test
