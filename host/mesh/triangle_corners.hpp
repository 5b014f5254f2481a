// A triangle's corners by local index (0, 1, 2, counter-clockwise): the next and previous corner, and
// where a point sits among them. Shared by the triangulators and the cleanup's editable mesh.
#pragma once
#include <array>

namespace pdmesh {

inline int next3(int i) { return i == 2 ? 0 : i + 1; }
inline int prev3(int i) { return i == 0 ? 2 : i - 1; }

// Local index of `value`, which the caller knows is in the triangle.
inline int index_of(const std::array<int, 3>& a, int value) { return a[0] == value ? 0 : (a[1] == value ? 1 : 2); }

}  // namespace pdmesh
