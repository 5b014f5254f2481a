// PNG files from cairo image surfaces, written with zlib directly: cairo's own writer goes through
// libpng at zlib's default level, which took about half the time of a 1600 px picture; a picture
// of lines and dots on white compresses as well at level 1 without a row filter, several times
// faster (docs/cli.md, "Pictures while the run goes on").
#pragma once
#include <cairo.h>

#include <filesystem>
#include <string>
#include <vector>

namespace pdmesh {

// The PNG bytes of an RGB24 or ARGB32 image surface (alpha dropped), or of an A8 one holding ink
// (a grey canvas: grey 255 - alpha, always greyscale), zlib at `level`: 8-bit
// greyscale when every pixel is grey (red = green = blue: a mesh picture without a value fill), one
// byte a pixel where RGB takes three, so a third of the bytes to deflate for the same pixels, with
// zlib's run-length strategy where the rows are mostly runs; else 8-bit RGB, zlib's default strategy. Throws Error when
// the surface is not an image surface of those formats or zlib fails.
std::string encode_png(cairo_surface_t* surface, int level = 1);

// Whether every pixel of an RGB24 or ARGB32 image surface has red = green = blue (true for an A8 one).
bool grey_surface(cairo_surface_t* surface);

// A picture drawn in horizontal bands (render_picture) is encoded band by band, each on the thread
// that drew it: its scanlines deflated on their own (raw deflate, ending in a sync flush unless it
// is the last band), with their Adler-32 and byte count. png_from_bands joins them, top to bottom,
// into one PNG (one zlib stream: the header, the bands' data, the combined Adler-32). One band gives
// encode_png's bytes. `grey` bands (grey_surface must hold) store one byte a pixel; the bands of one
// PNG are all grey or all RGB (png_from_bands throws Error otherwise).
struct DeflatedBand {
  std::string bytes;
  unsigned long adler = 1;
  std::size_t length = 0;  // scanline bytes, filter bytes included
  int width = 0, height = 0;
  bool grey = false;
};
DeflatedBand deflate_band(cairo_surface_t* surface, bool last, int level = 1, bool grey = false);
std::string png_from_bands(const std::vector<DeflatedBand>& bands);

// Writes `bytes` to `path` (not atomically: the caller writes to a temporary). Throws InputError
// naming the path when it cannot be written.
void write_bytes(const std::filesystem::path& path, const std::string& bytes);
// Writes encode_png(surface) to `path`, as write_bytes.
void write_png_file(const std::filesystem::path& path, cairo_surface_t* surface);

}  // namespace pdmesh
