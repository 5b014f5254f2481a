// Case-file texts for the tests that parse a case with parse_case_text: a nominal case path (nothing is
// read from it), a one-curve geometry, and spacing sections that make a run metric.
#pragma once
#include <filesystem>
#include <string>

namespace pdmesh_test {

inline const std::filesystem::path kCase = "/cases/demo/case.toml";
inline const std::string kGeometry = "[geometry]\nfiles = [\"a.crv\"]\n";
inline const std::string kMetric = "[spacing]\nfield = \"metric\"\nh1 = \"0.1\"\nh2 = \"0.01\"\n";
inline const std::string kHessian = "[spacing]\nfield = \"hessian\"\nfunction = \"x*x\"\ncomplexity = 100\n";

}  // namespace pdmesh_test
