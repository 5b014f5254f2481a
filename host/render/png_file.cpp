// PNG encoding with zlib; see png_file.hpp. Format: PNG specification, 2nd edition (W3C, 2003),
// https://www.w3.org/TR/png/ : signature, IHDR, IDAT (zlib stream of filtered scanlines), IEND, each
// chunk with a CRC-32 over its type and data.
#include "render/png_file.hpp"

#include <zlib.h>

#include <cstdint>
#include <fstream>
#include <vector>

#include <fmt/format.h>

#include "core/errors.hpp"

namespace pdmesh {
namespace {

void put32(std::string& out, std::uint32_t v) {
  out += static_cast<char>(v >> 24);
  out += static_cast<char>(v >> 16);
  out += static_cast<char>(v >> 8);
  out += static_cast<char>(v);
}

void chunk(std::string& out, const char* type, const std::string& data) {
  put32(out, static_cast<std::uint32_t>(data.size()));
  const std::size_t start = out.size();
  out.append(type, 4);
  out += data;
  uLong crc = crc32(0L, Z_NULL, 0);
  crc = crc32(crc, reinterpret_cast<const Bytef*>(out.data() + start), static_cast<uInt>(out.size() - start));
  put32(out, static_cast<std::uint32_t>(crc));
}

void check_surface(cairo_surface_t* surface) {
  if (cairo_surface_get_type(surface) != CAIRO_SURFACE_TYPE_IMAGE) throw Error("PNG encoder: not an image surface");
  const cairo_format_t format = cairo_image_surface_get_format(surface);
  if (format != CAIRO_FORMAT_RGB24 && format != CAIRO_FORMAT_ARGB32 && format != CAIRO_FORMAT_A8)
    throw Error("PNG encoder: the surface is neither RGB24, ARGB32 nor A8");
}

// An A8 surface holds ink (Canvas's grey pictures): its grey is 255 - alpha.
bool ink_surface(cairo_surface_t* surface) { return cairo_image_surface_get_format(surface) == CAIRO_FORMAT_A8; }

}  // namespace

bool grey_surface(cairo_surface_t* surface) {
  check_surface(surface);
  if (ink_surface(surface)) return true;
  cairo_surface_flush(surface);
  const int width = cairo_image_surface_get_width(surface);
  const int height = cairo_image_surface_get_height(surface);
  const int stride = cairo_image_surface_get_stride(surface);
  const unsigned char* data = cairo_image_surface_get_data(surface);
  for (int y = 0; y < height; ++y) {
    const auto* pixels = reinterpret_cast<const std::uint32_t*>(data + static_cast<std::ptrdiff_t>(y) * stride);
    std::uint32_t differ = 0;  // a whole row without a branch per pixel (vectorised)
    for (int x = 0; x < width; ++x) {
      const std::uint32_t p = pixels[x];
      differ |= ((p >> 16) ^ p) & 0xFFu;
      differ |= ((p >> 8) ^ p) & 0xFFu;
    }
    if (differ != 0) return false;
  }
  return true;
}

namespace {

// The share of the sampled pixels (every 16th row) equal to their left neighbour: the grey (one
// channel) or the whole RGB pixel.
double run_share(const unsigned char* data, int width, int height, int stride, bool ink, bool grey) {
  std::size_t equal = 0, total = 0;
  for (int y = 0; y < height; y += 16) {
    const unsigned char* row = data + static_cast<std::ptrdiff_t>(y) * stride;
    if (ink) {
      for (int x = 1; x < width; ++x) equal += row[x] == row[x - 1] ? 1 : 0;
    } else {
      const auto* pixels = reinterpret_cast<const std::uint32_t*>(row);
      const std::uint32_t mask = grey ? 0xFFu : 0xFFFFFFu;
      for (int x = 1; x < width; ++x) equal += ((pixels[x] ^ pixels[x - 1]) & mask) == 0 ? 1 : 0;
    }
    total += static_cast<std::size_t>(width > 1 ? width - 1 : 0);
  }
  return total > 0 ? static_cast<double>(equal) / static_cast<double>(total) : 1.0;
}

}  // namespace

DeflatedBand deflate_band(cairo_surface_t* surface, bool last, int level, bool grey) {
  check_surface(surface);
  cairo_surface_flush(surface);
  DeflatedBand band;
  band.width = cairo_image_surface_get_width(surface);
  band.height = cairo_image_surface_get_height(surface);
  band.grey = grey;
  const int stride = cairo_image_surface_get_stride(surface);
  const unsigned char* data = cairo_image_surface_get_data(surface);
  const std::size_t channels = grey ? 1 : 3;

  // Raw deflate (no zlib header or trailer: png_from_bands writes them once for all bands).
  z_stream z{};
  const bool ink = ink_surface(surface);
  const double runs = run_share(data, band.width, band.height, stride, ink, grey);
  // zlib's run-length strategy (matches one byte back only) for a grey band with at least a quarter
  // of its pixels equal to their left neighbour, else the default strategy. Mesh pictures with that
  // many runs come out about as small and compress about twice as fast under Z_RLE
  // (docs/performance.md, the pictures' row). Rows without runs (anti-aliased texture repeating at a
  // longer distance) need the default strategy's matches at any distance.
  const int strategy = grey && 4 * runs >= 1 ? Z_RLE : Z_DEFAULT_STRATEGY;
  // zlib's memory level: 6 for an RGB band of at least three quarters runs (a node picture of a
  // small run: a 16 kB hash table, in the core's first-level cache where the default 8's 64 kB is
  // not), as small a file; 8 for other RGB bands (a node picture shaded by the nodes' density:
  // faster and smaller at 8) and for grey ones (under Z_RLE no hash table; 8's larger symbol buffer
  // means fewer, cheaper blocks).
  const int mem_level = !grey && 4 * runs >= 3 ? 6 : 8;
  if (deflateInit2(&z, level, Z_DEFLATED, -15, mem_level, strategy) != Z_OK)
    throw Error("PNG encoder: deflateInit failed");
  std::vector<unsigned char> row(1 + channels * static_cast<std::size_t>(band.width));
  std::vector<unsigned char> buffer(1 << 16);
  const auto drain = [&](int flush) {
    do {
      z.next_out = buffer.data();
      z.avail_out = static_cast<uInt>(buffer.size());
      const int rc = deflate(&z, flush);
      if (rc == Z_STREAM_ERROR) {
        deflateEnd(&z);
        throw Error("PNG encoder: deflate failed");
      }
      band.bytes.append(reinterpret_cast<const char*>(buffer.data()), buffer.size() - z.avail_out);
    } while (z.avail_out == 0);
  };
  band.adler = adler32(0L, Z_NULL, 0);
  for (int y = 0; y < band.height; ++y) {
    const auto* pixels = reinterpret_cast<const std::uint32_t*>(data + static_cast<std::ptrdiff_t>(y) * stride);
    const unsigned char* alpha = data + static_cast<std::ptrdiff_t>(y) * stride;
    if (ink && grey) {
      for (int x = 0; x < band.width; ++x) row[1 + x] = static_cast<unsigned char>(255 - alpha[x]);
    } else if (ink) {
      for (int x = 0; x < band.width; ++x) row[1 + 3 * x] = row[2 + 3 * x] = row[3 + 3 * x] = 255 - alpha[x];
    } else if (grey) {
      for (int x = 0; x < band.width; ++x) row[1 + x] = static_cast<unsigned char>(pixels[x]);  // blue = red = green
    } else {
      for (int x = 0; x < band.width; ++x) {
        const std::uint32_t p = pixels[x];  // 0xAARRGGBB in native order
        row[1 + 3 * x] = static_cast<unsigned char>(p >> 16);
        row[2 + 3 * x] = static_cast<unsigned char>(p >> 8);
        row[3 + 3 * x] = static_cast<unsigned char>(p);
      }
    }
    // Filter type 0 (none): measured on a 30P30N mesh picture, level 1 then gives a smaller file
    // (0.98 MB) than the Sub or Up filters (1.16, 1.17 MB) or cairo's writer (1.10 MB), as fast.
    row[0] = 0;
    band.adler = adler32(band.adler, row.data(), static_cast<uInt>(row.size()));
    band.length += row.size();
    z.next_in = row.data();
    z.avail_in = static_cast<uInt>(row.size());
    drain(Z_NO_FLUSH);
  }
  z.next_in = nullptr;
  z.avail_in = 0;
  // A band that others follow ends with a sync flush: byte-aligned and without the final-block bit,
  // so the next band's deflate data may follow it (each band's back-references stay within itself).
  drain(last ? Z_FINISH : Z_SYNC_FLUSH);
  deflateEnd(&z);
  return band;
}

std::string png_from_bands(const std::vector<DeflatedBand>& bands) {
  if (bands.empty()) throw Error("PNG encoder: no surface");
  int height = 0;
  for (const DeflatedBand& b : bands) {
    if (b.width != bands.front().width) throw Error("PNG encoder: bands of different widths");
    if (b.grey != bands.front().grey) throw Error("PNG encoder: grey and RGB bands");
    height += b.height;
  }
  // The zlib stream: header (deflate, 32K window, level 1's "fastest" flag: what deflateInit2 writes
  // at level 1), the bands' deflate data, the Adler-32 of all the scanlines.
  std::string idat = "\x78\x01";
  uLong adler = adler32(0L, Z_NULL, 0);
  for (const DeflatedBand& b : bands) {
    idat += b.bytes;
    adler = adler32_combine(adler, b.adler, static_cast<z_off_t>(b.length));
  }
  put32(idat, static_cast<std::uint32_t>(adler));

  std::string out = "\x89PNG\r\n\x1a\n";
  std::string header;
  put32(header, static_cast<std::uint32_t>(bands.front().width));
  put32(header, static_cast<std::uint32_t>(height));
  header += '\x08';                                // bit depth
  header += bands.front().grey ? '\x00' : '\x02';  // colour type: greyscale or RGB
  header += '\x00';                                // compression: deflate
  header += '\x00';                                // filter method 0
  header += '\x00';                                // no interlace
  chunk(out, "IHDR", header);
  chunk(out, "IDAT", idat);
  chunk(out, "IEND", "");
  return out;
}

std::string encode_png(cairo_surface_t* surface, int level) {
  return png_from_bands({deflate_band(surface, true, level, grey_surface(surface))});
}

void write_bytes(const std::filesystem::path& path, const std::string& bytes) {
  std::ofstream f(path, std::ios::binary | std::ios::trunc);
  f.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  f.close();
  if (!f) throw InputError(fmt::format("cannot write '{}'", path.string()));
}

void write_png_file(const std::filesystem::path& path, cairo_surface_t* surface) {
  write_bytes(path, encode_png(surface));
}

}  // namespace pdmesh
