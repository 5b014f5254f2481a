// The PNG encoder (render/png_file): the file structure checked by hand against the PNG specification
// (signature, IHDR fields, chunk CRCs with zlib's crc32, the IDAT stream inflated with zlib's
// uncompress into filter bytes and RGB rows), and the pixels read back by libpng through cairo.
#include <catch2/catch.hpp>

#include <cairo.h>
#include <zlib.h>

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "core/errors.hpp"
#include "render/png_file.hpp"
#include "temp_files.hpp"

using namespace pdmesh;

namespace {

// A width x height RGB24 image surface whose pixel (x, y) is pixel(x, y) (0xAARRGGBB).
template <class Pixel>
cairo_surface_t* surface_of(int width, int height, Pixel pixel) {
  cairo_surface_t* s = cairo_image_surface_create(CAIRO_FORMAT_RGB24, width, height);
  cairo_surface_flush(s);
  for (int y = 0; y < height; ++y) {
    auto* row =
        reinterpret_cast<std::uint32_t*>(cairo_image_surface_get_data(s) + y * cairo_image_surface_get_stride(s));
    for (int x = 0; x < width; ++x) row[x] = pixel(x, y);
  }
  cairo_surface_mark_dirty(s);
  return s;
}

std::uint32_t be32(const std::string& s, std::size_t at) {
  return (static_cast<std::uint32_t>(static_cast<unsigned char>(s[at])) << 24) |
         (static_cast<std::uint32_t>(static_cast<unsigned char>(s[at + 1])) << 16) |
         (static_cast<std::uint32_t>(static_cast<unsigned char>(s[at + 2])) << 8) |
         static_cast<std::uint32_t>(static_cast<unsigned char>(s[at + 3]));
}

struct Chunk {
  std::string type, data;
};

// Splits a PNG into its chunks, checking the signature and every chunk's CRC-32.
std::vector<Chunk> chunks(const std::string& png) {
  REQUIRE(png.size() >= 8);
  REQUIRE(png.substr(0, 8) == std::string("\x89PNG\r\n\x1a\n", 8));
  std::vector<Chunk> out;
  std::size_t at = 8;
  while (at < png.size()) {
    REQUIRE(at + 12 <= png.size());
    const std::uint32_t length = be32(png, at);
    REQUIRE(at + 12 + length <= png.size());
    Chunk c{png.substr(at + 4, 4), png.substr(at + 8, length)};
    uLong crc = crc32(0L, Z_NULL, 0);
    crc = crc32(crc, reinterpret_cast<const Bytef*>(png.data() + at + 4), static_cast<uInt>(4 + length));
    INFO("chunk " << c.type);
    CHECK(be32(png, at + 8 + length) == static_cast<std::uint32_t>(crc));
    out.push_back(std::move(c));
    at += 12 + length;
  }
  return out;
}

// A width x height RGB24 (or ARGB32) surface whose pixel (x, y) has red 10x + y, green 7y, blue x + y.
cairo_surface_t* pattern(int width, int height, cairo_format_t format = CAIRO_FORMAT_RGB24) {
  cairo_surface_t* s = cairo_image_surface_create(format, width, height);
  cairo_surface_flush(s);
  unsigned char* data = cairo_image_surface_get_data(s);
  const int stride = cairo_image_surface_get_stride(s);
  for (int y = 0; y < height; ++y) {
    auto* row = reinterpret_cast<std::uint32_t*>(data + y * stride);
    for (int x = 0; x < width; ++x)
      row[x] = 0xFF000000u | (static_cast<std::uint32_t>(10 * x + y) << 16) | (static_cast<std::uint32_t>(7 * y) << 8) |
               static_cast<std::uint32_t>(x + y);
  }
  cairo_surface_mark_dirty(s);
  return s;
}

// The PNG bytes written to `file` and decoded by libpng (through cairo), ready to read.
cairo_surface_t* read_back(const std::filesystem::path& file, const std::string& png) {
  write_bytes(file, png);
  cairo_surface_t* back = cairo_image_surface_create_from_png(file.c_str());
  REQUIRE(cairo_surface_status(back) == CAIRO_STATUS_SUCCESS);
  cairo_surface_flush(back);
  return back;
}

}  // namespace

TEST_CASE("PNG encoder: signature, IHDR, CRCs and the inflated rows follow the specification", "[render][png]") {
  const int width = 13, height = 5;
  cairo_surface_t* surface = pattern(width, height);
  const std::string png = encode_png(surface);
  cairo_surface_destroy(surface);
  const std::vector<Chunk> parts = chunks(png);
  REQUIRE(parts.size() == 3);
  CHECK(parts[0].type == "IHDR");
  CHECK(parts[1].type == "IDAT");
  CHECK(parts[2].type == "IEND");
  CHECK(parts[2].data.empty());
  const std::string& h = parts[0].data;
  REQUIRE(h.size() == 13);
  CHECK(be32(h, 0) == static_cast<std::uint32_t>(width));
  CHECK(be32(h, 4) == static_cast<std::uint32_t>(height));
  CHECK(h[8] == 8);   // bit depth
  CHECK(h[9] == 2);   // truecolour (RGB)
  CHECK(h[10] == 0);  // deflate
  CHECK(h[11] == 0);  // adaptive filtering, method 0
  CHECK(h[12] == 0);  // not interlaced
  // The IDAT stream is one zlib stream of `height` rows: a filter byte, then RGB triples.
  const std::size_t row = 1 + 3 * static_cast<std::size_t>(width);
  std::vector<unsigned char> raw(row * height + 16);
  uLongf size = static_cast<uLongf>(raw.size());
  REQUIRE(uncompress(raw.data(), &size, reinterpret_cast<const Bytef*>(parts[1].data.data()),
                     static_cast<uLong>(parts[1].data.size())) == Z_OK);
  REQUIRE(size == row * height);
  for (int y = 0; y < height; ++y) {
    const unsigned char* r = &raw[static_cast<std::size_t>(y) * row];
    CHECK(r[0] == 0);  // filter type None
    for (int x = 0; x < width; ++x) {
      INFO("pixel " << x << ", " << y);
      CHECK(r[1 + 3 * x] == 10 * x + y);
      CHECK(r[2 + 3 * x] == 7 * y);
      CHECK(r[3 + 3 * x] == x + y);
    }
  }
  // Every compression level gives the same pixels.
  cairo_surface_t* again = pattern(width, height);
  for (const int level : {0, 6, 9}) {
    const std::vector<Chunk> p = chunks(encode_png(again, level));
    std::vector<unsigned char> r(row * height);
    uLongf n = static_cast<uLongf>(r.size());
    REQUIRE(uncompress(r.data(), &n, reinterpret_cast<const Bytef*>(p[1].data.data()),
                       static_cast<uLong>(p[1].data.size())) == Z_OK);
    CHECK(std::vector<unsigned char>(raw.begin(), raw.begin() + static_cast<std::ptrdiff_t>(row * height)) == r);
  }
  cairo_surface_destroy(again);
}

TEST_CASE("PNG encoder: libpng (through cairo) reads back the written pixels, alpha dropped", "[render][png]") {
  const auto dir = pdmesh_test::fresh_dir("png_file");
  for (const cairo_format_t format : {CAIRO_FORMAT_RGB24, CAIRO_FORMAT_ARGB32}) {
    INFO("format " << static_cast<int>(format));
    cairo_surface_t* surface = pattern(300, 17, format);
    const auto file = dir / "p.png";
    write_png_file(file, surface);
    cairo_surface_t* back = cairo_image_surface_create_from_png(file.c_str());
    REQUIRE(cairo_surface_status(back) == CAIRO_STATUS_SUCCESS);
    REQUIRE(cairo_image_surface_get_width(back) == 300);
    REQUIRE(cairo_image_surface_get_height(back) == 17);
    CHECK(cairo_image_surface_get_format(back) == CAIRO_FORMAT_RGB24);  // no alpha channel in the file
    cairo_surface_flush(back);
    std::size_t differ = 0;
    for (int y = 0; y < 17; ++y) {
      const auto* a = reinterpret_cast<const std::uint32_t*>(cairo_image_surface_get_data(surface) +
                                                             y * cairo_image_surface_get_stride(surface));
      const auto* b = reinterpret_cast<const std::uint32_t*>(cairo_image_surface_get_data(back) +
                                                             y * cairo_image_surface_get_stride(back));
      for (int x = 0; x < 300; ++x) differ += (a[x] & 0xFFFFFFu) != (b[x] & 0xFFFFFFu);
    }
    CHECK(differ == 0);
    cairo_surface_destroy(back);
    cairo_surface_destroy(surface);
  }
  std::filesystem::remove_all(dir);
}

TEST_CASE("PNG encoder: other surfaces and unwritable paths are errors", "[render][png]") {
  cairo_surface_t* bits = cairo_image_surface_create(CAIRO_FORMAT_A1, 4, 4);
  CHECK_THROWS_AS(encode_png(bits), Error);
  cairo_surface_destroy(bits);
  cairo_surface_t* recording = cairo_recording_surface_create(CAIRO_CONTENT_COLOR, nullptr);
  CHECK_THROWS_AS(encode_png(recording), Error);
  cairo_surface_destroy(recording);
  cairo_surface_t* ok = pattern(2, 2);
  const auto missing = std::filesystem::temp_directory_path() / "pdmesh_no_such_dir_png" / "x.png";
  CHECK_THROWS_AS(write_png_file(missing, ok), InputError);
  CHECK_THROWS_WITH(write_png_file(missing, ok), Catch::Contains("x.png"));
  cairo_surface_destroy(ok);
}

TEST_CASE("PNG encoder: bands deflated apart join into one valid stream of the whole picture's rows", "[render][png]") {
  // A 37 x 300 pattern cut into bands of 1, 120 and 179 rows: the joined PNG inflates (zlib checks
  // the combined Adler-32) to the rows of the whole surface's PNG; one band is encode_png's bytes.
  const int width = 37, height = 300;
  cairo_surface_t* whole = pattern(width, height);
  const std::string reference = encode_png(whole);
  std::vector<cairo_surface_t*> parts;
  std::vector<DeflatedBand> deflated;
  const int cuts[] = {0, 1, 121, height};
  for (int k = 0; k < 3; ++k) {
    const int rows = cuts[k + 1] - cuts[k];
    cairo_surface_t* band = cairo_image_surface_create(CAIRO_FORMAT_RGB24, width, rows);
    cairo_surface_flush(whole);
    cairo_surface_flush(band);
    const int stride = cairo_image_surface_get_stride(whole);
    for (int y = 0; y < rows; ++y)
      std::copy_n(cairo_image_surface_get_data(whole) + (cuts[k] + y) * stride, 4 * width,
                  cairo_image_surface_get_data(band) + y * cairo_image_surface_get_stride(band));
    cairo_surface_mark_dirty(band);
    deflated.push_back(deflate_band(band, k == 2));
    parts.push_back(band);
  }
  const std::string joined = png_from_bands(deflated);
  const auto inflated = [&](const std::string& png) {
    const std::vector<Chunk> c = chunks(png);
    REQUIRE(c.size() == 3);
    CHECK(be32(c[0].data, 0) == static_cast<std::uint32_t>(width));
    CHECK(be32(c[0].data, 4) == static_cast<std::uint32_t>(height));
    std::vector<unsigned char> rows(static_cast<std::size_t>(height) * (1 + 3 * width) + 16);
    uLongf size = rows.size();
    REQUIRE(uncompress(rows.data(), &size, reinterpret_cast<const Bytef*>(c[1].data.data()),
                       static_cast<uLong>(c[1].data.size())) == Z_OK);
    rows.resize(size);
    return rows;
  };
  CHECK(inflated(joined) == inflated(reference));
  CHECK(inflated(joined).size() == static_cast<std::size_t>(height) * (1 + 3 * width));
  // A band that is not the last ends without the final-block bit: used as the last, it would end the
  // stream early; and one band on its own is the single-surface encoder's output, byte for byte.
  CHECK(png_from_bands({deflate_band(whole, true)}) == reference);
  CHECK_THROWS_AS(png_from_bands({}), Error);
  for (cairo_surface_t* s : parts) cairo_surface_destroy(s);
  cairo_surface_destroy(whole);
}

TEST_CASE("PNG encoder: an A8 surface of ink is written as 8-bit greyscale, grey 255 - alpha", "[render][png]") {
  // A 300 x 17 surface of ink (long runs of none, a ramp, runs of one level), alone and as the
  // bands of one picture.
  const int width = 300, height = 17;
  cairo_surface_t* ink = cairo_image_surface_create(CAIRO_FORMAT_A8, width, height);
  cairo_surface_flush(ink);
  const auto level = [](int x, int y) { return x < 100 ? 0 : x < 200 ? (x + 3 * y) % 256 : 115; };
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      cairo_image_surface_get_data(ink)[y * cairo_image_surface_get_stride(ink) + x] =
          static_cast<unsigned char>(level(x, y));
  cairo_surface_mark_dirty(ink);
  CHECK(grey_surface(ink));
  const std::string png = encode_png(ink);
  const std::vector<Chunk> parts = chunks(png);
  REQUIRE(parts.size() == 3);
  CHECK(parts[0].data[9] == 0);  // colour type: greyscale
  const auto dir = pdmesh_test::fresh_dir("png_ink");
  const auto file = dir / "ink.png";
  cairo_surface_t* back = read_back(file, png);
  std::size_t differ = 0;
  for (int y = 0; y < height; ++y) {
    const auto* b = reinterpret_cast<const std::uint32_t*>(cairo_image_surface_get_data(back) +
                                                           y * cairo_image_surface_get_stride(back));
    for (int x = 0; x < width; ++x) {
      const std::uint32_t g = 255u - static_cast<std::uint32_t>(level(x, y));
      differ += (b[x] & 0xFFFFFFu) != ((g << 16) | (g << 8) | g);
    }
  }
  CHECK(differ == 0);
  cairo_surface_destroy(back);
  // Written as RGB (a band of a picture with colour elsewhere), each pixel's three channels are its grey.
  const DeflatedBand rgb = deflate_band(ink, true, 1, false);
  std::vector<unsigned char> raw((1 + 3 * width) * height + 16);
  uLongf size = static_cast<uLongf>(raw.size());
  z_stream z{};
  REQUIRE(inflateInit2(&z, -15) == Z_OK);
  std::string bytes = rgb.bytes;
  z.next_in = reinterpret_cast<Bytef*>(bytes.data());
  z.avail_in = static_cast<uInt>(rgb.bytes.size());
  z.next_out = raw.data();
  z.avail_out = static_cast<uInt>(raw.size());
  CHECK(inflate(&z, Z_FINISH) == Z_STREAM_END);
  size = z.total_out;
  inflateEnd(&z);
  REQUIRE(size == static_cast<uLongf>((1 + 3 * width) * height));
  differ = 0;
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      for (int c = 0; c < 3; ++c)
        differ += raw[static_cast<std::size_t>(y * (1 + 3 * width) + 1 + 3 * x + c)] != 255 - level(x, y);
  CHECK(differ == 0);
  cairo_surface_destroy(ink);
  std::filesystem::remove_all(dir);
}

TEST_CASE("PNG encoder: a grey picture is written as 8-bit greyscale with the same pixels, a coloured one as RGB",
          "[render][png]") {
  // A 300 x 17 surface of greys (long runs of white, a ramp, runs of one grey), then the same with
  // one pixel coloured.
  const int width = 300, height = 17;
  const auto grey_pattern = [&](bool one_coloured) {
    return surface_of(width, height, [&](int x, int y) {
      if (one_coloured && x == 250 && y == 9) return 0xFF000000u | (140u << 16) | (140u << 8) | 141u;  // blue above
      const std::uint32_t g = x < 100 ? 255u : x < 200 ? static_cast<std::uint32_t>((x + 3 * y) % 256) : 140u;
      return 0xFF000000u | (g << 16) | (g << 8) | g;
    });
  };
  const auto dir = pdmesh_test::fresh_dir("png_grey");
  for (const bool coloured : {false, true}) {
    INFO("one pixel coloured " << coloured);
    cairo_surface_t* surface = grey_pattern(coloured);
    CHECK(grey_surface(surface) == !coloured);
    const std::string png = encode_png(surface);
    const std::vector<Chunk> parts = chunks(png);
    REQUIRE(parts.size() == 3);
    CHECK(parts[0].data[9] == (coloured ? 2 : 0));  // colour type: RGB or greyscale
    // The inflated rows: a filter byte, then one byte a pixel (grey) or three (RGB).
    const std::size_t channels = coloured ? 3 : 1;
    const std::size_t row = 1 + channels * width;
    std::vector<unsigned char> raw(row * height + 16);
    uLongf size = static_cast<uLongf>(raw.size());
    REQUIRE(uncompress(raw.data(), &size, reinterpret_cast<const Bytef*>(parts[1].data.data()),
                       static_cast<uLong>(parts[1].data.size())) == Z_OK);
    CHECK(size == row * height);
    // libpng reads back every pixel as drawn.
    const auto file = dir / "g.png";
    cairo_surface_t* back = read_back(file, png);
    std::size_t differ = 0;
    for (int y = 0; y < height; ++y) {
      const auto* a = reinterpret_cast<const std::uint32_t*>(cairo_image_surface_get_data(surface) +
                                                             y * cairo_image_surface_get_stride(surface));
      const auto* b = reinterpret_cast<const std::uint32_t*>(cairo_image_surface_get_data(back) +
                                                             y * cairo_image_surface_get_stride(back));
      for (int x = 0; x < width; ++x) differ += (a[x] & 0xFFFFFFu) != (b[x] & 0xFFFFFFu);
    }
    CHECK(differ == 0);
    cairo_surface_destroy(back);
    // Grey and RGB bands do not make one PNG.
    if (!coloured) {
      cairo_surface_t* rgb = pattern(width, 3);
      CHECK_THROWS_AS(png_from_bands({deflate_band(surface, false, 1, true), deflate_band(rgb, true)}), Error);
      cairo_surface_destroy(rgb);
    }
    cairo_surface_destroy(surface);
  }
  std::filesystem::remove_all(dir);
}

TEST_CASE("PNG encoder: a picture without runs of one colour, grey or RGB, is as small as zlib's matches make it",
          "[render][png]") {
  // Pixels repeating every 7 (no two neighbours equal): nothing for zlib's run-length strategy (one
  // byte back), everything for its default strategy's matches 7 pixels back.
  const int width = 400, height = 60;
  for (const bool grey : {true, false}) {
    INFO((grey ? "grey" : "RGB"));
    cairo_surface_t* s = surface_of(width, height, [&](int x, int y) {
      const auto k = static_cast<std::uint32_t>((x + y) % 7);
      return grey ? 0xFF000000u | ((30 * k + 10) * 0x010101u)
                  : 0xFF000000u | ((40 * k) << 16) | ((255 - 30 * k) << 8) | (17 * k + 3);
    });
    const std::string png = encode_png(s);
    const std::size_t raw = static_cast<std::size_t>(height) * (1 + (grey ? 1 : 3) * width);
    INFO("PNG bytes " << png.size() << " for " << raw << " bytes of scanlines");
    CHECK(png.size() < raw / 10);
    const std::vector<Chunk> parts = chunks(png);
    CHECK(static_cast<unsigned char>(parts[0].data[9]) == (grey ? 0 : 2));  // IHDR colour type
    std::vector<unsigned char> rows(raw + 16);
    uLongf size = static_cast<uLongf>(rows.size());
    REQUIRE(uncompress(rows.data(), &size, reinterpret_cast<const Bytef*>(parts[1].data.data()),
                       static_cast<uLong>(parts[1].data.size())) == Z_OK);
    CHECK(size == raw);
    CHECK(rows[1 + (grey ? 1 : 3) * 5] == (grey ? 30 * 5 + 10 : 40 * 5));  // pixel (5, 0): k = 5
    cairo_surface_destroy(s);
  }
}
