// Whole-mesh lists from the kept scores, on several threads in slot order (mesh_lists.hpp).
#include "cleanup/mesh_lists.hpp"

#include <algorithm>
#include <atomic>

#include "core/parallel.hpp"

namespace pdmesh::cleanup {
namespace {

constexpr std::size_t kBlock = 16384;

std::size_t blocks_of(std::size_t n) { return (n + kBlock - 1) / kBlock; }

}  // namespace

std::vector<int> vertices_of_bad_triangles(const EditableMesh& m, const std::vector<double>& score, double limit,
                                           std::vector<std::uint8_t>& mark, std::size_t threads) {
  mark.assign(static_cast<std::size_t>(m.vertex_slots()), 0);
  const auto slots = static_cast<std::size_t>(m.triangle_slots());
  // Two triangles of different threads may mark the same vertex: both store 1.
  parallel_for(
      blocks_of(slots),
      [&](std::size_t b) {
        const std::size_t end = std::min(slots, (b + 1) * kBlock);
        for (std::size_t slot = b * kBlock; slot < end; ++slot) {
          const int t = static_cast<int>(slot);
          if (!m.alive(t) || !(score[slot] < limit)) continue;
          for (int a : m.v[t])
            std::atomic_ref<std::uint8_t>(mark[static_cast<std::size_t>(a)]).store(1, std::memory_order_relaxed);
        }
      },
      1, threads);
  const std::size_t vertices = mark.size();
  std::vector<std::vector<int>> part(blocks_of(vertices));
  parallel_for(
      part.size(),
      [&](std::size_t b) {
        const std::size_t end = std::min(vertices, (b + 1) * kBlock);
        for (std::size_t a = b * kBlock; a < end; ++a)
          if (mark[a]) part[b].push_back(static_cast<int>(a));
      },
      1, threads);
  std::size_t total = 0;
  for (const auto& p : part) total += p.size();
  std::vector<int> out;
  out.reserve(total);
  for (const auto& p : part) out.insert(out.end(), p.begin(), p.end());
  return out;
}

std::vector<std::pair<double, int>> bad_triangles(const EditableMesh& m, const std::vector<double>& score, double below,
                                                  const std::function<bool(int)>& keep, std::size_t threads) {
  const auto slots = static_cast<std::size_t>(m.triangle_slots());
  std::vector<std::vector<std::pair<double, int>>> part(blocks_of(slots));
  parallel_for(
      part.size(),
      [&](std::size_t b) {
        const std::size_t end = std::min(slots, (b + 1) * kBlock);
        for (std::size_t slot = b * kBlock; slot < end; ++slot) {
          const int t = static_cast<int>(slot);
          if (!m.alive(t)) continue;
          const double q = score[slot];
          if (q < below && keep(t)) part[b].push_back({q, t});
        }
      },
      1, threads);
  std::size_t total = 0;
  for (const auto& p : part) total += p.size();
  std::vector<std::pair<double, int>> out;
  out.reserve(total);
  for (const auto& p : part) out.insert(out.end(), p.begin(), p.end());
  // Distinct triangles: the sorted list does not depend on the order they were found in.
  std::sort(out.begin(), out.end());
  return out;
}

ScoreScan scan_scores(const EditableMesh& m, const std::vector<double>& score, double target, std::size_t threads) {
  const auto slots = static_cast<std::size_t>(m.triangle_slots());
  struct Part {
    double worst = 1.0;
    std::size_t count = 0;
    std::vector<double> shortfall;  // target - score of the triangles below target, in slot order
  };
  std::vector<Part> part(blocks_of(slots));
  parallel_for(
      part.size(),
      [&](std::size_t b) {
        Part& p = part[b];
        const std::size_t end = std::min(slots, (b + 1) * kBlock);
        for (std::size_t slot = b * kBlock; slot < end; ++slot) {
          if (!m.alive(static_cast<int>(slot))) continue;
          const double q = score[slot];
          p.worst = std::min(p.worst, q);
          if (q < target) p.shortfall.push_back(target - q);
          ++p.count;
        }
      },
      1, threads);
  ScoreScan s;
  std::size_t count = 0;
  for (const Part& p : part) {
    s.worst = std::min(s.worst, p.worst);
    count += p.count;
    for (double d : p.shortfall) s.deficit += d;
  }
  s.count = static_cast<double>(count);
  return s;
}

}  // namespace pdmesh::cleanup
