// RunDeflater: see deflate_runs.hpp. Format: RFC 1951 (DEFLATE), sections 3.2.5 (length and
// distance codes) and 3.2.6 (the fixed Huffman codes); bits are packed from the least significant
// end of each byte, Huffman codes from their most significant bit.
#include "render/deflate_runs.hpp"

#include <array>
#include <cstring>

#include "core/errors.hpp"

namespace pdmesh {
namespace {

std::uint32_t reversed(std::uint32_t code, int bits) {
  std::uint32_t r = 0;
  for (int i = 0; i < bits; ++i) r |= ((code >> i) & 1u) << (bits - 1 - i);
  return r;
}

// The fixed codes, ready to pack: a literal's code and length; a match length's code with its extra
// bits above it, and their total length.
struct FixedCodes {
  std::array<std::uint32_t, 256> literal_bits{};
  std::array<int, 256> literal_count{};
  std::array<std::uint32_t, 259> length_bits{};
  std::array<int, 259> length_count{};
  std::uint32_t end_bits = 0;  // symbol 256, end of block
  int end_count = 7;

  FixedCodes() {
    const auto symbol_code = [](int s, std::uint32_t& bits, int& count) {
      std::uint32_t code = 0;
      if (s < 144) {
        code = 0x30u + static_cast<std::uint32_t>(s), count = 8;
      } else if (s < 256) {
        code = 0x190u + static_cast<std::uint32_t>(s - 144), count = 9;
      } else if (s < 280) {
        code = static_cast<std::uint32_t>(s - 256), count = 7;
      } else {
        code = 0xC0u + static_cast<std::uint32_t>(s - 280), count = 8;
      }
      bits = reversed(code, count);
    };
    for (int b = 0; b < 256; ++b) symbol_code(b, literal_bits[b], literal_count[b]);
    symbol_code(256, end_bits, end_count);
    static constexpr int kBase[29] = {3,  4,  5,  6,  7,  8,  9,  10, 11,  13,  15,  17,  19,  23, 27,
                                      31, 35, 43, 51, 59, 67, 83, 99, 115, 131, 163, 195, 227, 258};
    static constexpr int kExtra[29] = {0, 0, 0, 0, 0, 0, 0, 0, 1, 1, 1, 1, 2, 2, 2,
                                       2, 3, 3, 3, 3, 4, 4, 4, 4, 5, 5, 5, 5, 0};
    for (int length = 3; length <= 258; ++length) {
      int s = 0;
      while (s + 1 < 29 && kBase[s + 1] <= length) ++s;  // 258 is symbol 285's alone
      std::uint32_t bits = 0;
      int count = 0;
      symbol_code(257 + s, bits, count);
      length_bits[length] = bits | (static_cast<std::uint32_t>(length - kBase[s]) << count);
      length_count[length] = count + kExtra[s];
    }
  }
};

const FixedCodes& fixed_codes() {
  static const FixedCodes codes;
  return codes;
}

}  // namespace

RunDeflater::RunDeflater(int pixel_bytes, bool last) : pixel_bytes_(pixel_bytes), last_(last) {
  if (pixel_bytes < 1 || pixel_bytes > 4) throw Error("PNG encoder: runs of 1 to 4 bytes a pixel");
  // Distances 1 to 4 are distance codes 0 to 3, 5 bits, no extra bits.
  distance_code_ = reversed(static_cast<std::uint32_t>(pixel_bytes - 1), 5);
  put(last ? 1 : 0, 1);  // BFINAL
  put(1, 2);             // BTYPE 01: fixed Huffman codes
}

void RunDeflater::put(std::uint32_t bits, int count) {
  pending_ |= static_cast<std::uint64_t>(bits) << pending_count_;
  pending_count_ += count;
  if (pending_count_ >= 32) {
    char word[4];
    for (int i = 0; i < 4; ++i) word[i] = static_cast<char>(pending_ >> (8 * i));
    out_.append(word, 4);
    pending_ >>= 32;
    pending_count_ -= 32;
  }
}

void RunDeflater::literal(unsigned char byte) {
  ++literals_;
  const FixedCodes& c = fixed_codes();
  put(c.literal_bits[byte], c.literal_count[byte]);
}

void RunDeflater::match(std::size_t length) {
  const FixedCodes& c = fixed_codes();
  while (length > 0) {
    // Pieces of at most 258 bytes, none under 3.
    const std::size_t piece = length <= 258 ? length : (length - 258 >= 3 ? 258 : length - 3);
    put(c.length_bits[piece], c.length_count[piece]);
    put(distance_code_, 5);
    length -= piece;
  }
}

void RunDeflater::row(const unsigned char* bytes, std::size_t length) {
  const auto d = static_cast<std::size_t>(pixel_bytes_);
  bytes_ += length;
  std::size_t at = 0;
  for (; at < length && at < d; ++at) literal(bytes[at]);
  while (at < length) {
    // The run's length: bytes equal to the byte a pixel before, 8 at a time while they last.
    std::size_t end = at;
    while (end + 8 <= length) {
      std::uint64_t a = 0, b = 0;
      std::memcpy(&a, bytes + end, 8);
      std::memcpy(&b, bytes + end - d, 8);
      if (a != b) break;
      end += 8;
    }
    while (end < length && bytes[end] == bytes[end - d]) ++end;
    if (end - at >= 3) {
      match(end - at);
      at = end;
    } else {
      literal(bytes[at]);
      ++at;
    }
  }
}

void RunDeflater::align() {
  if (pending_count_ % 8 != 0) put(0, 8 - pending_count_ % 8);
  while (pending_count_ > 0) {
    out_ += static_cast<char>(pending_ & 0xFFu);
    pending_ >>= 8;
    pending_count_ -= 8;
  }
  pending_ = 0;
  pending_count_ = 0;
}

std::string RunDeflater::finish() {
  const FixedCodes& c = fixed_codes();
  put(c.end_bits, c.end_count);
  if (!last_) {
    put(0, 3);  // an empty stored block, not final: BFINAL 0, BTYPE 00, then LEN 0, NLEN 0xFFFF
    align();
    out_.append("\x00\x00\xFF\xFF", 4);
  } else {
    align();
  }
  return std::move(out_);
}

}  // namespace pdmesh
