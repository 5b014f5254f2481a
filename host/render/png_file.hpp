// PNG files from cairo image surfaces, written with zlib directly: cairo's own writer goes through
// libpng at zlib's default level, which took about half the time of a 1600 px picture; a picture
// of lines and dots on white compresses as well at level 1 without a row filter, several times
// faster (docs/performance.md, "Pictures").
#pragma once
#include <cairo.h>

#include <filesystem>
#include <string>
#include <vector>

namespace pdmesh {

// The PNG bytes (8-bit RGB, no alpha) of an RGB24 or ARGB32 image surface (alpha dropped).
// Throws Error when the surface is not an image surface of those formats or zlib fails.
std::string encode_png(cairo_surface_t* surface, int level = 1);
// One PNG of image surfaces of equal width stacked top to bottom (a picture drawn in bands).
std::string encode_png(const std::vector<cairo_surface_t*>& bands, int level = 1);

// Writes encode_png(surface) to `path` (not atomically: the caller writes to a temporary).
// Throws InputError naming the path when it cannot be written.
void write_png_file(const std::filesystem::path& path, cairo_surface_t* surface);
void write_png_file(const std::filesystem::path& path, const std::vector<cairo_surface_t*>& bands);

}  // namespace pdmesh
