// Sweeps in strips: two colours of strips in parallel, then the vertices they left on one thread.
#include "cleanup/strip_sweeps.hpp"

#include <algorithm>
#include <chrono>
#include <cstdlib>

#include "cleanup/strip_schedule.hpp"
#include "core/parallel.hpp"

namespace pdmesh::cleanup {

StripSweeps::StripSweeps(const EditableMesh& mesh, int strips, std::size_t threads) : threads_(threads) {
  std::vector<double> xs;
  xs.reserve(static_cast<std::size_t>(mesh.vertex_slots()));
  for (int a = 0; a < mesh.vertex_slots(); ++a)
    if (!mesh.removed(a)) xs.push_back(mesh.p[a].x);
  std::sort(xs.begin(), xs.end());
  strips = std::max(strips, 2);
  for (int k = 1; k < strips && !xs.empty(); ++k)
    edges_.push_back(xs[xs.size() * static_cast<std::size_t>(k) / static_cast<std::size_t>(strips)]);
  initial_ = mesh.vertex_slots();
  label_.resize(static_cast<std::size_t>(initial_));
  parallel_for(
      label_.size(), [&](std::size_t a) { label_[a] = strip_of(mesh.p[a].x); }, 16384, sweep_thread_limit(threads_));
}

int StripSweeps::strip_of(double x) const {
  return static_cast<int>(std::upper_bound(edges_.begin(), edges_.end(), x) - edges_.begin());
}

// Vertices added by the topology passes (and slots a rolled-back trial freed and a later one reused)
// take the strip of where they are now.
void StripSweeps::label_new(const EditableMesh& mesh) {
  label_.resize(static_cast<std::size_t>(mesh.vertex_slots()));
  for (int a = initial_; a < mesh.vertex_slots(); ++a) label_[a] = strip_of(mesh.p[a].x);
}

// A star's spokes lie between two of its triangles or on the boundary, so what lies across them is in
// the star already.
bool StripSweeps::inside(const EditableMesh& mesh, int a, int s, std::vector<int>& fan) const {
  if (mesh.removed(a) || !mesh.movable(a)) return true;  // relax() and climb() write nothing then
  auto near = [&](int x) { return std::abs(label_[x] - s) <= 1; };
  if (mesh.prev[a] >= 0 && !near(mesh.prev[a])) return false;
  if (mesh.next[a] >= 0 && !near(mesh.next[a])) return false;
  mesh.star(a, fan);
  for (int t : fan) {
    const auto& tv = mesh.v[t];
    const int k = EditableMesh::index_of(tv, a);
    if (label_[tv[next3(k)]] != s || label_[tv[prev3(k)]] != s) return false;
    const int u = mesh.n[t][k];
    if (u >= 0 && !near(mesh.v[u][EditableMesh::index_of(mesh.n[u], t)])) return false;
  }
  return true;
}

SweepTally StripSweeps::sweep(EditableMesh& mesh, Smoother& serial, const std::vector<int>& list, SweepMove move,
                              const std::function<bool(int)>& worth, InterruptPoll& poll) {
  label_new(mesh);
  const int n = strips();
  std::vector<std::vector<int>> bucket(static_cast<std::size_t>(n)), later(bucket.size());
  for (int a : list) bucket[static_cast<std::size_t>(label_[a])].push_back(a);  // ascending within each
  std::vector<SweepTally> tally(bucket.size());
  auto step = [move](Smoother& smoother, int a) {
    return move == SweepMove::Relax ? smoother.relax(a) : smoother.climb(a);
  };
  auto run_strip = [&](int s) {
    Smoother smoother = serial;  // its settings; its own buffers
    smoother.set_defer_flips(true);
    const auto k = static_cast<std::size_t>(s);
    for (int a : bucket[k]) {
      if (!worth(a)) continue;
      // inside() leaves a's star in the smoother's buffer wherever the move needs it.
      if (!inside(mesh, a, s, smoother.star_buffer())) {
        later[k].push_back(a);
        continue;
      }
      const bool moved = move == SweepMove::Relax ? smoother.relax_with_star(a) : smoother.climb_with_star(a);
      if (smoother.deferred())
        later[k].push_back(a);
      else if (moved)
        tally[k].add(smoother.last_gain());
    }
  };
  const auto start = std::chrono::steady_clock::now();
  std::vector<std::size_t> work(bucket.size());
  for (std::size_t k = 0; k < bucket.size(); ++k) work[k] = bucket[k].size();
  run_strips(n, work, run_strip, sweep_thread_limit(threads_));
  parallel_seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::vector<int> rest;
  for (const auto& l : later) rest.insert(rest.end(), l.begin(), l.end());
  std::sort(rest.begin(), rest.end());
  SweepTally total;
  for (const SweepTally& t : tally) total.add(t);  // in strip order, whatever thread made them
  taken_ += list.size() - rest.size();
  left_ += rest.size();
  SweepTally tail;
  const auto serial_start = std::chrono::steady_clock::now();
  for (int a : rest) {
    poll.tick();
    if (worth(a) && step(serial, a)) tail.add(serial.last_gain());
  }
  serial_seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - serial_start).count();
  total.add(tail);
  return total;
}

}  // namespace pdmesh::cleanup
