// The cleanup's whole-mesh lists from the kept triangle scores (cleanup.cpp): the vertices of the bad
// triangles for the sweeps, the bad triangles for the topology pass, and the mesh's worst score and
// shortfall for settling. Each is read on several threads in blocks of triangle (or vertex) slots and
// put together in slot order, so the list, and every sum, is the one a single pass in slot order makes.
#pragma once
#include <cstddef>
#include <cstdint>
#include <functional>
#include <utility>
#include <vector>

#include "cleanup/editable_mesh.hpp"

namespace pdmesh::cleanup {

// The vertices of the live triangles t with score[t] < limit, ascending. mark: scratch, one byte per
// vertex slot afterwards (1: listed).
std::vector<int> vertices_of_bad_triangles(const EditableMesh& m, const std::vector<double>& score, double limit,
                                           std::vector<std::uint8_t>& mark, std::size_t threads);

// The live triangles t with score[t] < below for which keep(t) holds, as (score, t), sorted. keep is
// called on several threads at once: it may only read.
std::vector<std::pair<double, int>> bad_triangles(const EditableMesh& m, const std::vector<double>& score, double below,
                                                  const std::function<bool(int)>& keep, std::size_t threads);

// Over the live triangles: the smallest score (1 when none is smaller), their count, and the shortfall
// sum of (target - score) over those below target, added in slot order.
struct ScoreScan {
  double worst = 1.0, count = 0.0, deficit = 0.0;
};
ScoreScan scan_scores(const EditableMesh& m, const std::vector<double>& score, double target, std::size_t threads);

}  // namespace pdmesh::cleanup
