// healing.png: what healing changed (geometry/heal.hpp): the curves as read in grey, the removed
// parts in red, the new parts in blue, and a circle around every change (most are far smaller than
// a pixel of the whole picture).
#pragma once
#include <filesystem>
#include <string>
#include <vector>

#include "geometry/heal.hpp"

namespace pdmesh {

// Writes a .png or .svg atomically.
void write_heal_picture(const std::filesystem::path& path, const std::vector<std::vector<Vec2>>& input,
                        const HealResult& result, const std::string& title, int long_side = 1600);

}  // namespace pdmesh
