// Binary VTK XML data arrays: base64, raw bytes, block headers and zlib blocks (see vtu_data.hpp).
#include "io/vtu_data.hpp"

#include <zlib.h>

#include <algorithm>
#include <array>
#include <cstring>
#include <limits>

#include <fmt/format.h>

#include "core/errors.hpp"
#include "core/input_file.hpp"

namespace pdmesh {
namespace {

constexpr char kBase64Alphabet[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";

// 0..63 for a base64 character, -1 for anything else (the alphabet inverted); by table, since large
// arrays decode hundreds of millions of characters.
constexpr std::array<signed char, 256> kBase64Values = [] {
  std::array<signed char, 256> t{};
  for (auto& v : t) v = -1;
  for (int i = 0; i < 64; ++i) t[static_cast<unsigned char>(kBase64Alphabet[i])] = static_cast<signed char>(i);
  return t;
}();
int base64_value(char c) { return kBase64Values[static_cast<unsigned char>(c)]; }

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

void Base64Encoder::put(const void* data, std::size_t n) {
  const auto* p = static_cast<const unsigned char*>(data);
  while (n > 0) {
    const std::size_t take = std::min(n, sizeof buffer_ - used_);
    std::memcpy(buffer_ + used_, p, take);
    used_ += take;
    p += take;
    n -= take;
    if (used_ == sizeof buffer_) flush_whole_groups();
  }
}

// Encodes every whole 3-byte group of the buffer and keeps the 0-2 bytes left over.
void Base64Encoder::flush_whole_groups() {
  const std::size_t whole = used_ - used_ % 3;
  const std::size_t start = out_.size();
  out_.resize(start + whole / 3 * 4);
  char* o = out_.data() + start;
  for (std::size_t i = 0; i < whole; i += 3) {
    const unsigned v = (unsigned{buffer_[i]} << 16) | (unsigned{buffer_[i + 1]} << 8) | buffer_[i + 2];
    *o++ = kBase64Alphabet[(v >> 18) & 63];
    *o++ = kBase64Alphabet[(v >> 12) & 63];
    *o++ = kBase64Alphabet[(v >> 6) & 63];
    *o++ = kBase64Alphabet[v & 63];
  }
  std::memmove(buffer_, buffer_ + whole, used_ - whole);
  used_ -= whole;
}

void Base64Encoder::finish() {
  flush_whole_groups();
  if (used_ == 0) return;
  const unsigned v = (unsigned{buffer_[0]} << 16) | (used_ == 2 ? unsigned{buffer_[1]} << 8 : 0u);
  out_ += kBase64Alphabet[(v >> 18) & 63];
  out_ += kBase64Alphabet[(v >> 12) & 63];
  out_ += used_ == 2 ? kBase64Alphabet[(v >> 6) & 63] : '=';
  out_ += '=';
  used_ = 0;
}

bool parse_vtu_type(std::string_view name, VtuType& type) {
  struct Entry {
    const char* name;
    VtuType type;
  };
  // The XML names, then the legacy names VTK still accepts.
  static constexpr Entry kTypes[] = {
      {"Int8", {1, false, true}},         {"UInt8", {1, false, false}},         {"Int16", {2, false, true}},
      {"UInt16", {2, false, false}},      {"Int32", {4, false, true}},          {"UInt32", {4, false, false}},
      {"Int64", {8, false, true}},        {"UInt64", {8, false, false}},        {"Float32", {4, true, true}},
      {"Float64", {8, true, true}},       {"Char", {1, false, true}},           {"UnsignedChar", {1, false, false}},
      {"Short", {2, false, true}},        {"UnsignedShort", {2, false, false}}, {"Int", {4, false, true}},
      {"UnsignedInt", {4, false, false}}, {"Float", {4, true, true}},           {"Double", {8, true, true}},
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
    if (is_xml_space(c)) continue;
    if (c == '=') {
      ++padding;
      values[n++] = 0;
      continue;
    }
    const int v = base64_value(c);
    if (v < 0 || padding > 0) {
      throw InputError(fmt::format("{}: invalid base64 character '{}'", where_, quote_input(std::string_view(&c, 1))));
    }
    values[n++] = v;
  }
  if (n == 0) return false;
  if (n < 4 || padding > 2) throw InputError(fmt::format("{}: base64 data ends in the middle of a group", where_));
  const std::uint32_t word = (static_cast<std::uint32_t>(values[0]) << 18) |
                             (static_cast<std::uint32_t>(values[1]) << 12) |
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
    throw InputError(
        fmt::format("{}: the data ends before {} ({} bytes wanted, at most {} left)", where_, what, n, available()));
  }
  out.reserve(out.size() + n);
  if (!base64_) {
    const auto* p = reinterpret_cast<const unsigned char*>(text_.data() + pos_);
    out.insert(out.end(), p, p + n);
    pos_ += n;
    return;
  }
  while (n > 0) {
    // Fast path: whole groups of four plain characters (no white space, no padding) decode straight
    // into `out`; anything else goes through next_group(), which checks and reports it.
    if (pending_pos_ == pending_count_) {
      const std::size_t start = out.size();
      std::size_t groups = std::min(n / 3, (text_.size() - pos_) / 4);
      out.resize(start + 3 * groups);
      unsigned char* o = out.data() + start;
      const char* t = text_.data() + pos_;
      std::size_t done = 0;
      for (; done < groups; ++done, t += 4) {
        const int a = base64_value(t[0]), b = base64_value(t[1]), c = base64_value(t[2]), d = base64_value(t[3]);
        if ((a | b | c | d) < 0) break;
        const auto word = (static_cast<std::uint32_t>(a) << 18) | (static_cast<std::uint32_t>(b) << 12) |
                          (static_cast<std::uint32_t>(c) << 6) | static_cast<std::uint32_t>(d);
        *o++ = static_cast<unsigned char>(word >> 16);
        *o++ = static_cast<unsigned char>(word >> 8);
        *o++ = static_cast<unsigned char>(word);
      }
      out.resize(start + 3 * done);
      pos_ += 4 * done;
      n -= 3 * done;
      if (n == 0) break;
    }
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
      throw InputError(
          fmt::format("{}: the header announces {} bytes but at most {} follow", bytes.where(), n, bytes.available()));
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
        throw InputError(
            fmt::format("{}: compressed block {} of {} bytes runs past the end of the data", bytes.where(), b, csize));
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
