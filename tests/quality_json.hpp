// Values read from the quality.json that pdmesh mesh writes, for tests that check its figures.
#pragma once
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

namespace pdmesh_test {

// The number after "key": in quality.json's spacing_conformance object.
inline double conformance_value(const std::filesystem::path& quality_json, const std::string& key) {
  std::ifstream f(quality_json);
  const std::string text(std::istreambuf_iterator<char>(f), {});
  const auto object = text.find("\"spacing_conformance\"");
  REQUIRE(object != std::string::npos);
  const auto at = text.find("\"" + key + "\": ", object);
  REQUIRE(at != std::string::npos);
  return std::stod(text.substr(at + key.size() + 4));
}

// The whole quality.json, for tests that check its figures by their keys
// (q["boundary_layer"]["tables"][0]["max_angle"]).
inline nlohmann::json read_quality_json(const std::filesystem::path& quality_json) {
  std::ifstream f(quality_json);
  REQUIRE(f.good());
  return nlohmann::json::parse(f);
}

}  // namespace pdmesh_test
