// Binary VTK XML data arrays: base64, raw bytes, block headers and zlib blocks (see vtu_data.hpp).
#include "io/vtu_data.hpp"

#include <zlib.h>

#include <algorithm>
#include <cstring>
#include <limits>

#include <fmt/format.h>

#include "core/errors.hpp"

namespace pdmesh {
namespace {

// 0..63 for a base64 character, -1 for anything else.
int base64_value(char c) {
  if (c >= 'A' && c <= 'Z') return c - 'A';
  if (c >= 'a' && c <= 'z') return c - 'a' + 26;
  if (c >= '0' && c <= '9') return c - '0' + 52;
  if (c == '+') return 62;
  if (c == '/') return 63;
  return -1;
}

bool is_space(char c) { return c == ' ' || c == '\n' || c == '\r' || c == '\t'; }

// An unsigned integer of `bytes` bytes in the file's byte order.
std::uint64_t load_unsigned(const unsigned char* p, int bytes, bool big_endian) {
  std::uint64_t v = 0;
  for (int k = 0; k < bytes; ++k) {
    const int i = big_endian ? k : bytes - 1 - k;
    v = (v << 8) | p[i];
  }
  return v;
}

double load_value(const unsigned char* p, const VtuType& t, bool big_endian) {
  const std::uint64_t bits = load_unsigned(p, t.bytes, big_endian);
  if (t.is_float) {
    if (t.bytes == 4) {
      float f;
      const auto b32 = static_cast<std::uint32_t>(bits);
      std::memcpy(&f, &b32, 4);
      return f;
    }
    double d;
    std::memcpy(&d, &bits, 8);
    return d;
  }
  if (!t.is_signed) return static_cast<double>(bits);
  // Sign-extend from the element width.
  const int shift = 64 - 8 * t.bytes;
  const auto s = static_cast<std::int64_t>(bits << shift) >> shift;
  return static_cast<double>(s);
}

}  // namespace

bool parse_vtu_type(std::string_view name, VtuType& type) {
  struct Entry {
    const char* name;
    VtuType type;
  };
  // The XML names, then the legacy names VTK still accepts.
  static constexpr Entry kTypes[] = {
      {"Int8", {1, false, true}},      {"UInt8", {1, false, false}},    {"Int16", {2, false, true}},
      {"UInt16", {2, false, false}},   {"Int32", {4, false, true}},     {"UInt32", {4, false, false}},
      {"Int64", {8, false, true}},     {"UInt64", {8, false, false}},   {"Float32", {4, true, true}},
      {"Float64", {8, true, true}},    {"Char", {1, false, true}},      {"UnsignedChar", {1, false, false}},
      {"Short", {2, false, true}},     {"UnsignedShort", {2, false, false}}, {"Int", {4, false, true}},
      {"UnsignedInt", {4, false, false}}, {"Float", {4, true, true}},   {"Double", {8, true, true}},
  };
  for (const Entry& e : kTypes) {
    if (name == e.name) {
      type = e.type;
      return true;
    }
  }
  return false;
}

VtuBytes::VtuBytes(std::string_view text, bool is_base64, std::string where)
    : text_(text), base64_(is_base64), where_(std::move(where)) {}

VtuBytes VtuBytes::base64(std::string_view text, std::string where) { return VtuBytes(text, true, std::move(where)); }
VtuBytes VtuBytes::raw(std::string_view bytes, std::string where) { return VtuBytes(bytes, false, std::move(where)); }

std::size_t VtuBytes::available() const {
  const std::size_t rest = text_.size() - pos_;
  return static_cast<std::size_t>(pending_count_ - pending_pos_) + (base64_ ? rest / 4 * 3 + 3 : rest);
}

// A padded group ("xx==" or "xxx=") ends one base64 stream; VTK writes a block header and its data
// as separate streams, so decoding simply continues with the next group.
bool VtuBytes::next_group() {
  int values[4];
  int n = 0;
  int padding = 0;
  while (n < 4 && pos_ < text_.size()) {
    const char c = text_[pos_++];
    if (is_space(c)) continue;
    if (c == '=') {
      ++padding;
      values[n++] = 0;
      continue;
    }
    const int v = base64_value(c);
    if (v < 0 || padding > 0) {
      throw InputError(fmt::format("{}: invalid base64 character '{}'", where_, c));
    }
    values[n++] = v;
  }
  if (n == 0) return false;
  if (n < 4 || padding > 2) throw InputError(fmt::format("{}: base64 data ends in the middle of a group", where_));
  const std::uint32_t word = (static_cast<std::uint32_t>(values[0]) << 18) | (static_cast<std::uint32_t>(values[1]) << 12) |
                             (static_cast<std::uint32_t>(values[2]) << 6) | static_cast<std::uint32_t>(values[3]);
  pending_[0] = static_cast<unsigned char>(word >> 16);
  pending_[1] = static_cast<unsigned char>(word >> 8);
  pending_[2] = static_cast<unsigned char>(word);
  pending_count_ = 3 - padding;
  pending_pos_ = 0;
  return true;
}

void VtuBytes::read(std::size_t n, std::vector<unsigned char>& out, std::string_view what) {
  if (n > available()) {
    throw InputError(fmt::format("{}: the data ends before {} ({} bytes wanted, at most {} left)", where_, what, n,
                                 available()));
  }
  out.reserve(out.size() + n);
  if (!base64_) {
    const auto* p = reinterpret_cast<const unsigned char*>(text_.data() + pos_);
    out.insert(out.end(), p, p + n);
    pos_ += n;
    return;
  }
  while (n > 0) {
    if (pending_pos_ == pending_count_ && !next_group()) {
      throw InputError(fmt::format("{}: the data ends before {}", where_, what));
    }
    const auto take = std::min<std::size_t>(n, static_cast<std::size_t>(pending_count_ - pending_pos_));
    out.insert(out.end(), pending_ + pending_pos_, pending_ + pending_pos_ + take);
    pending_pos_ += static_cast<int>(take);
    n -= take;
  }
}

std::vector<double> decode_vtu_binary(VtuBytes& bytes, const VtuEncoding& encoding, const VtuType& type) {
  const int hb = encoding.header_uint64 ? 8 : 4;
  std::vector<unsigned char> header;
  auto header_item = [&](std::size_t i) { return load_unsigned(header.data() + i * hb, hb, encoding.big_endian); };
  std::vector<unsigned char> payload;
  if (encoding.compressor == VtuCompressor::None) {
    // Header: the number of data bytes that follow.
    bytes.read(hb, header, "the block header");
    const std::uint64_t n = header_item(0);
    if (n > bytes.available()) {
      throw InputError(fmt::format("{}: the header announces {} bytes but at most {} follow", bytes.where(), n,
                                   bytes.available()));
    }
    bytes.read(static_cast<std::size_t>(n), payload, "the end of the array");
  } else {
    // Header: number of blocks, uncompressed block size, uncompressed size of the last block
    // (0: a full block), then the compressed size of every block.
    bytes.read(3 * static_cast<std::size_t>(hb), header, "the compression header");
    const std::uint64_t blocks = header_item(0);
    const std::uint64_t block_size = header_item(1);
    const std::uint64_t last_size = header_item(2) == 0 ? block_size : header_item(2);
    if (blocks > bytes.available() / static_cast<std::uint64_t>(hb) || (blocks > 0 && block_size == 0) ||
        last_size > block_size || block_size > std::numeric_limits<std::uint32_t>::max()) {
      throw InputError(fmt::format("{}: implausible compression header ({} blocks of {} bytes, last {})", bytes.where(),
                                   blocks, block_size, last_size));
    }
    bytes.read(static_cast<std::size_t>(blocks) * static_cast<std::size_t>(hb), header, "the compressed block sizes");
    std::vector<unsigned char> compressed;
    for (std::uint64_t b = 0; b < blocks; ++b) {
      const std::uint64_t csize = header_item(3 + b);
      if (csize > bytes.available()) {
        throw InputError(fmt::format("{}: compressed block {} of {} bytes runs past the end of the data", bytes.where(), b,
                                     csize));
      }
      compressed.clear();
      bytes.read(static_cast<std::size_t>(csize), compressed, fmt::format("the end of compressed block {}", b));
      const std::uint64_t want = b + 1 == blocks ? last_size : block_size;
      // Deflate expands at most about 1032:1: a larger claim is a damaged header, refused before
      // anything that large is allocated.
      if (want > 1032 * csize + 1024) {
        throw InputError(fmt::format("{}: compressed block {} of {} bytes cannot hold the {} bytes its header says",
                                     bytes.where(), b, csize, want));
      }
      const std::size_t at = payload.size();
      payload.resize(at + static_cast<std::size_t>(want));
      uLongf got = static_cast<uLongf>(want);
      const int rc = uncompress(payload.data() + at, &got, compressed.data(), static_cast<uLong>(compressed.size()));
      if (rc != Z_OK || got != want) {
        throw InputError(fmt::format("{}: zlib block {} does not inflate to its {} bytes ({})", bytes.where(), b, want,
                                     rc == Z_OK ? fmt::format("got {}", got) : std::string(zError(rc))));
      }
    }
  }
  if (payload.size() % static_cast<std::size_t>(type.bytes) != 0) {
    throw InputError(fmt::format("{}: {} data bytes are not a whole number of {}-byte values", bytes.where(),
                                 payload.size(), type.bytes));
  }
  std::vector<double> values(payload.size() / static_cast<std::size_t>(type.bytes));
  for (std::size_t i = 0; i < values.size(); ++i) {
    values[i] = load_value(payload.data() + i * static_cast<std::size_t>(type.bytes), type, encoding.big_endian);
  }
  return values;
}

}  // namespace pdmesh
