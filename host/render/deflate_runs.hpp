// A raw deflate stream (RFC 1951) of PNG scanlines made of runs and literals only: a byte that
// repeats the one a pixel before it (a run of one colour: the white paper, a line's inside) is a
// match at the distance of one pixel, every other byte a literal, all in one block of the fixed
// Huffman codes. zlib at level 1 searches matches at every distance and builds its own codes, at
// about a nanosecond a byte, most of a picture's encoding; this finds its matches with 8-byte
// compares and writes each symbol with one table look-up, several times faster, for files about a
// quarter larger on pdmesh's pictures (lines and dots on white).
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>

namespace pdmesh {

class RunDeflater {
 public:
  // `pixel_bytes`: the distance of a run's matches (1 for greyscale, 3 for RGB); 1 to 4. `last`: the
  // block is the stream's final one; otherwise finish() ends it like zlib's Z_SYNC_FLUSH (an empty
  // stored block, byte-aligned), so that another stream's blocks may follow it.
  RunDeflater(int pixel_bytes, bool last);
  // Appends a scanline (the filter byte and the pixels' bytes). Matches reach back into the
  // scanline only, so each scanline stands alone.
  void row(const unsigned char* bytes, std::size_t length);
  // The deflate data of every row so far; the deflater is spent.
  std::string finish();
  // The share of the rows' bytes written as literals (0 before the first row): where it is large
  // (a dense node picture's anti-aliased density, no runs), zlib's matches at every distance and its
  // own codes make a file several times smaller.
  double literal_share() const {
    return bytes_ > 0 ? static_cast<double>(literals_) / static_cast<double>(bytes_) : 0.0;
  }

 private:
  void put(std::uint32_t bits, int count);
  void literal(unsigned char byte);
  void match(std::size_t length);  // any length >= 3, at the distance of one pixel
  void align();                    // to the next byte boundary

  int pixel_bytes_;
  bool last_;
  std::uint32_t distance_code_;  // the fixed 5-bit code of the distance, bit-reversed
  std::string out_;
  std::size_t bytes_ = 0, literals_ = 0;
  std::uint64_t pending_ = 0;  // bits not yet in out_, least significant first
  int pending_count_ = 0;
};

}  // namespace pdmesh
