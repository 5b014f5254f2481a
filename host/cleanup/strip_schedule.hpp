// The order in which the strips of one sweep run on the threads (cleanup/strip_sweeps.hpp): every
// even strip may run at once, an odd strip once its even neighbours have returned. No barrier between
// the two colours: an odd strip reads and writes only its own strip and its two neighbours, which no
// even strip still running touches (those are two or more strips away), so the moves are those of
// running all even strips and then all odd ones, whichever thread takes which strip and when.
#pragma once
#include <cstddef>
#include <functional>
#include <vector>

namespace pdmesh::cleanup {

// Calls run(s) once for every strip s in [0, strips) on up to `threads` threads (at most the
// hardware's), run(s) for an odd s only after run(s - 1) and run(s + 1) (those that exist) have
// returned. Among the strips free to start, the one with the most work (work[s]; ties: the lower s)
// starts first, so that a long strip is not left to the end while the other threads wait for it.
// An exception thrown by run is rethrown once the strips already running have returned; no strip
// starts after it. A stop request (core/interrupt) ends it between strips with Interrupted.
void run_strips(int strips, const std::vector<std::size_t>& work, const std::function<void(int)>& run,
                std::size_t threads);

}  // namespace pdmesh::cleanup
