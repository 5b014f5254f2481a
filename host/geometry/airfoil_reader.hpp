// Reader for airfoil coordinate files in the UIUC database's two layouts, Selig and Lednicer
// (docs/geometry-input.md, "Airfoil files"): the points are split at the leading edge into the
// curves `upper` and `lower`, plus `te` closing a blunt trailing edge.
#pragma once
#include <string>
#include <vector>

#include "geometry/geometry.hpp"
#include "geometry/reader_text.hpp"

namespace pdmesh {

struct AirfoilFile {
  std::vector<RawCurve> curves;    // upper, lower[, te], named so
  std::vector<std::string> notes;  // what was repaired (repeated points dropped), for stderr
};

// True when the token lines are the workshop's count format (.crv/.dat blocks): the first line is a
// single number (the point count). Otherwise a .dat file is an airfoil file.
bool is_count_format(const std::vector<detail::TokenLine>& lines);

// Reads a Selig or Lednicer file (already split into token lines). InputError naming FILE:LINE and
// the value for a malformed point line, fewer than 3 distinct points or an empty file.
AirfoilFile read_airfoil_lines(const std::string& path, const std::vector<detail::TokenLine>& lines);

}  // namespace pdmesh
