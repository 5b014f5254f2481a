// What healing changed, as text: one stderr line per kind of change (count and the worst instance)
// and the "healing" object of quality.json (counts and every change with its coordinates).
#pragma once
#include <string>
#include <vector>

#include "geometry/heal.hpp"

namespace pdmesh {

// One line per kind that occurred, e.g. "healing: 3 merged vertices (worst: 0.3 apart, h 1000, at
// (12.5, 40), coast.crv:17 curve coast)". Empty when nothing changed.
std::vector<std::string> heal_report_lines(const HealResult& result);

// {"counts": {...}, "changes": [{"kind", "curve", "file", "line", "at", "size", "h", "removed",
// "added"}, ...]}; numbers with 17 significant digits.
std::string heal_json(const HealResult& result);

}  // namespace pdmesh
