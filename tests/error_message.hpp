// The message of the typed error a call throws, for tests that check what a refusal says.
#pragma once
#include <string>

namespace pdmesh_test {

// The what() of the E that `f` throws, or "" when it throws none (any other exception propagates).
template <class E, class F>
std::string error_message(F&& f) {
  try {
    f();
  } catch (const E& e) {
    return e.what();
  }
  return "";
}

}  // namespace pdmesh_test
