// A PNG read back through cairo, for tests that look at a picture's pixels.
#pragma once
#include <cairo.h>

#include <cstdint>
#include <filesystem>

#include "render/canvas.hpp"

namespace pdmesh_test {

// pixel() gives 0-255 channels.
struct Png {
  cairo_surface_t* s;
  explicit Png(const std::filesystem::path& p) : s(cairo_image_surface_create_from_png(p.c_str())) {}
  ~Png() { cairo_surface_destroy(s); }
  Png(const Png&) = delete;
  Png& operator=(const Png&) = delete;
  bool ok() const { return cairo_surface_status(s) == CAIRO_STATUS_SUCCESS; }
  int width() const { return cairo_image_surface_get_width(s); }
  int height() const { return cairo_image_surface_get_height(s); }
  pdmesh::Rgb pixel(int x, int y) const {
    cairo_surface_flush(s);
    const unsigned char* row = cairo_image_surface_get_data(s) + y * cairo_image_surface_get_stride(s);
    const auto v = *reinterpret_cast<const std::uint32_t*>(row + 4 * x);
    return {static_cast<double>((v >> 16) & 255), static_cast<double>((v >> 8) & 255), static_cast<double>(v & 255)};
  }
};

}  // namespace pdmesh_test
