// The run deflater (render/deflate_runs): its streams inflated by zlib give back the rows, for runs
// of every length around the 258-byte match limit, literals between them, and streams joined at a
// sync-flush ending.
#include <catch2/catch.hpp>

#include <zlib.h>

#include <algorithm>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "core/errors.hpp"
#include "render/deflate_runs.hpp"

using namespace pdmesh;

namespace {

// Raw inflate (no zlib header) of `deflated`; REQUIREs that the stream ends where the data ends.
std::vector<unsigned char> inflate_raw(const std::string& deflated, std::size_t expected) {
  z_stream z{};
  REQUIRE(inflateInit2(&z, -15) == Z_OK);
  std::vector<unsigned char> out(expected + 64);
  z.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(deflated.data()));
  z.avail_in = static_cast<uInt>(deflated.size());
  z.next_out = out.data();
  z.avail_out = static_cast<uInt>(out.size());
  const int rc = inflate(&z, Z_FINISH);
  CHECK(rc == Z_STREAM_END);
  CHECK(z.avail_in == 0);
  out.resize(out.size() - z.avail_out);
  inflateEnd(&z);
  return out;
}

// A scanline of `pixel_bytes`-byte pixels: the filter byte, then runs of one pixel of the given
// lengths (in pixels), each run's pixel different from the one before, with single random pixels
// between runs.
std::vector<unsigned char> row_of_runs(int pixel_bytes, const std::vector<int>& runs, std::mt19937& rng) {
  std::vector<unsigned char> row{0};
  std::vector<unsigned char> pixel(static_cast<std::size_t>(pixel_bytes), 255);
  for (const int run : runs) {
    for (int k = 0; k < run; ++k) row.insert(row.end(), pixel.begin(), pixel.end());
    for (auto& b : pixel) b = static_cast<unsigned char>(rng());
    row.insert(row.end(), pixel.begin(), pixel.end());
    pixel[0] = static_cast<unsigned char>(pixel[0] + 1);  // the next run differs from this pixel
  }
  return row;
}

}  // namespace

TEST_CASE("run deflater: zlib inflates its stream to the rows, runs of every length and literals between",
          "[render][png]") {
  std::mt19937 rng(7);
  // Runs (in pixels) around the match pieces' limits: 258 bytes is 258 grey or 86 RGB pixels.
  const std::vector<int> runs = {0,   1,   2,   3,   4,   5,   85,  86,  87,  88,  171, 172, 173,
                                 257, 258, 259, 260, 261, 262, 515, 516, 517, 518, 519, 1600};
  for (const int pixel_bytes : {1, 3, 4}) {
    INFO("bytes a pixel " << pixel_bytes);
    RunDeflater deflater(pixel_bytes, true);
    std::vector<unsigned char> all;
    for (int r = 0; r < 5; ++r) {
      std::vector<int> shuffled = runs;
      std::shuffle(shuffled.begin(), shuffled.end(), rng);
      const std::vector<unsigned char> row = row_of_runs(pixel_bytes, shuffled, rng);
      deflater.row(row.data(), row.size());
      all.insert(all.end(), row.begin(), row.end());
    }
    // A row of random bytes (no runs) and a row of one value.
    std::vector<unsigned char> noise(301), flat(4801, 0xFF);
    for (auto& b : noise) b = static_cast<unsigned char>(rng());
    deflater.row(noise.data(), noise.size());
    deflater.row(flat.data(), flat.size());
    all.insert(all.end(), noise.begin(), noise.end());
    all.insert(all.end(), flat.begin(), flat.end());
    CHECK(deflater.literal_share() < 0.25);  // the runs are matches, not literals
    const std::string deflated = deflater.finish();
    CHECK(inflate_raw(deflated, all.size()) == all);
    CHECK(deflated.size() < all.size() / 4);
  }
}

TEST_CASE("run deflater: a stream that is not the last ends byte-aligned for another to follow", "[render][png]") {
  std::mt19937 rng(11);
  std::vector<unsigned char> all;
  std::string joined;
  for (int part = 0; part < 3; ++part) {
    RunDeflater deflater(3, part == 2);
    for (int r = 0; r < 1 + part; ++r) {
      const std::vector<unsigned char> row = row_of_runs(3, {part, 90 * r, 7}, rng);
      deflater.row(row.data(), row.size());
      all.insert(all.end(), row.begin(), row.end());
    }
    const std::string bytes = deflater.finish();
    if (part < 2) {
      REQUIRE(bytes.size() >= 4);
      CHECK(bytes.substr(bytes.size() - 4) == std::string("\x00\x00\xFF\xFF", 4));  // the empty stored block
    }
    joined += bytes;
  }
  CHECK(inflate_raw(joined, all.size()) == all);
  // Random bytes are literals, all but the filter byte's neighbours that happen to repeat.
  RunDeflater noise(3, true);
  std::vector<unsigned char> bytes(3001);
  for (auto& b : bytes) b = static_cast<unsigned char>(rng());
  noise.row(bytes.data(), bytes.size());
  CHECK(noise.literal_share() > 0.99);
  CHECK_THROWS_AS(RunDeflater(0, true), Error);
  CHECK_THROWS_AS(RunDeflater(5, true), Error);
}
