// The text of many similar items (a mesh's points and triangles, a node file's lines) formatted on
// several threads: the items are cut into blocks, each block is formatted into a buffer of its own,
// and the buffers go to the sink in block order, so the text is exactly the one a loop over the items
// appends. The writers of million-node meshes spent seconds of one core in number formatting.
#pragma once
#include <algorithm>
#include <cstddef>
#include <string>
#include <vector>

#include "core/parallel.hpp"
#include "core/text_sink.hpp"

namespace pdmesh {

// Items per block, and blocks formatted per round: a round's buffers (~32 x 4096 lines) bound the
// memory, and a block's text (under 1 MB for lines under 256 characters) fits the room a bound
// TextSink keeps beyond its piece.
inline constexpr std::size_t kTextBlockItems = 4096;
inline constexpr std::size_t kTextBlocksPerRound = 32;

// Appends, for i = 0 .. n - 1 in order, what format(out, i) appends to `out` to `sink`. format must
// append item i's text and depend on i alone (blocks of items run on up to `threads` threads; 0:
// parallel_for's own limit). The sink gets whole blocks and writes out its pieces between them.
template <class Format>
void append_items(TextSink& sink, std::size_t n, const Format& format, std::size_t threads = 0) {
  std::vector<std::string> texts(std::min(kTextBlocksPerRound, (n + kTextBlockItems - 1) / kTextBlockItems));
  for (std::size_t first = 0; first < n; first += kTextBlocksPerRound * kTextBlockItems) {
    const std::size_t blocks = std::min(kTextBlocksPerRound, (n - first + kTextBlockItems - 1) / kTextBlockItems);
    parallel_for(
        blocks,
        [&](std::size_t b) {
          std::string& out = texts[b];
          out.clear();
          const std::size_t begin = first + b * kTextBlockItems, end = std::min(n, begin + kTextBlockItems);
          for (std::size_t i = begin; i < end; ++i) format(out, i);
        },
        1, threads == 0 ? 8 : threads);
    for (std::size_t b = 0; b < blocks; ++b) {
      sink.text() += texts[b];
      sink.piece_done();
    }
  }
}

}  // namespace pdmesh
