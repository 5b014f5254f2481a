// The cleanup's smoothing sweeps on several threads, with a result that does not depend on how many
// (issue 41; docs/cleanup.md, "Sweeps in strips"). The mesh is cut into strips along x; the vertices
// of the even strips are swept (each strip in ascending vertex order, the strips in parallel), then
// those of the odd strips (each once its two even neighbours are done: strip_schedule.hpp), then, on
// one thread and in ascending order, the vertices a strip could not take: those whose star reaches
// another strip, or whose move would need Lawson flips. So the strips fix the order of the moves, not
// the threads.
//
// Why two strips of one colour never meet: a vertex swept in a strip has its star in that strip and
// the vertices across its star's edges in that strip or a neighbouring one, and its move (without
// flips) writes only its own position and arc and the dirty marks of its star, all in its strip, and
// reads only positions of its star and across it. Two strips of one colour have a strip of the other
// colour between them, which does not move meanwhile, and no flip changes the topology.
#pragma once
#include <cstddef>
#include <functional>
#include <limits>
#include <vector>

#include "cleanup/editable_mesh.hpp"
#include "cleanup/smoothing.hpp"
#include "core/interrupt.hpp"

namespace pdmesh::cleanup {

// What a sweep's accepted moves gained (CleanupIteration's sweep fields), summed in a fixed order.
struct SweepTally {
  std::size_t moves = 0;
  std::size_t small_moves = 0;  // ... of which lowered their star's mean aspect ratio by < 1e-4
  double aspect_drop = 0.0, small_aspect_drop = 0.0;
  void add(const MoveGain& g) { count_move(*this, g); }
  void add(const SweepTally& t) { add_moves(*this, t); }
};

enum class SweepMove { Relax, Climb };

// The most threads the cleanup's parallel loops use for CleanupOptions::threads (0: no limit but the
// hardware's, which parallel_for applies). Every loop's result is the same on any number.
inline std::size_t sweep_thread_limit(std::size_t threads) {
  return threads == 0 ? std::numeric_limits<std::size_t>::max() : threads;
}

class StripSweeps {
 public:
  // Cuts the mesh into `strips` (>= 2) strips along x with equal numbers of its live vertices, and
  // labels each vertex with its strip. The labels stay for the whole cleanup (the moves are small);
  // vertices added later are labelled at the start of each sweep. threads: at most this many threads
  // (sweep_thread_limit's).
  StripSweeps(const EditableMesh& mesh, int strips, std::size_t threads);

  int strips() const { return static_cast<int>(edges_.size()) + 1; }

  // One sweep of `move` over `list` (vertices, ascending) with the settings of `serial`, which also
  // makes the moves the strips leave. A vertex is tried only where worth(a) holds when its turn comes
  // (read by several threads: it must only read the mesh's dirty marks and data fixed for the sweep).
  SweepTally sweep(EditableMesh& mesh, Smoother& serial, const std::vector<int>& list, SweepMove move,
                   const std::function<bool(int)>& worth, InterruptPoll& poll);

  // How many vertices the strips took and how many they left to the serial pass, over all sweeps.
  std::size_t taken() const { return taken_; }
  std::size_t left() const { return left_; }
  // Wall seconds in the two colours' parallel loops, over all sweeps (the rest of a sweep is serial).
  double parallel_seconds() const { return parallel_seconds_; }
  // Wall seconds in the serial pass over the vertices the strips left, over all sweeps.
  double serial_seconds() const { return serial_seconds_; }

  // The strip of vertex a (a slot labelled at construction or by the last sweep).
  int strip_of_vertex(int a) const { return label_[static_cast<std::size_t>(a)]; }
  // The independence rule: whether strip s may move a. Its star's vertices are all in s, the vertices
  // across its link edges (the edges opposite a, which Smoother::flips_needed tests) in s or a
  // neighbouring strip, and so are its neighbours along its curve (whose arcs bound its slide). Also
  // true for a vertex no move writes (removed, or fixed). When a may move and the test reaches the
  // star, `fan` holds a's star afterwards (whatever the answer).
  bool inside(const EditableMesh& mesh, int a, int s, std::vector<int>& fan) const;

 private:
  int strip_of(double x) const;
  void label_new(const EditableMesh& mesh);

  std::vector<double> edges_;  // the x of each strip's upper edge, ascending (strips - 1 values)
  std::vector<int> label_;     // per vertex slot: its strip
  int initial_ = 0;            // the slots labelled at construction; later ones are labelled per sweep
  std::size_t threads_;
  std::size_t taken_ = 0, left_ = 0;
  double parallel_seconds_ = 0.0, serial_seconds_ = 0.0;
};

}  // namespace pdmesh::cleanup
