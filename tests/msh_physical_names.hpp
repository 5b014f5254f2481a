// The $PhysicalNames section of an MSH file's text, for tests of the groups and tags a writer gives.
#pragma once
#include <sstream>
#include <string>
#include <vector>

namespace pdmesh_test {

// The lines between $PhysicalNames and $EndPhysicalNames, the count line first.
inline std::vector<std::string> physical_names(const std::string& msh) {
  std::istringstream in(msh);
  std::vector<std::string> out;
  std::string line;
  bool inside = false;
  while (std::getline(in, line)) {
    if (line == "$EndPhysicalNames") break;
    if (inside) out.push_back(line);
    inside = inside || line == "$PhysicalNames";
  }
  return out;
}

}  // namespace pdmesh_test
