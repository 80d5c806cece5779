// Image: an 8-bit RGBA picture in memory, and PNG reading and writing.
#pragma once

#include <cstdint>
#include <filesystem>
#include <vector>

#include "util/result.h"

namespace emboss {

struct Rect {
  int x = 0, y = 0, w = 0, h = 0;
  bool empty() const { return w <= 0 || h <= 0; }
  int area() const { return empty() ? 0 : w * h; }
};

// Rows top to bottom, 4 bytes a pixel (R, G, B, A). Not thread-safe for writes to the same pixel.
struct Image {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> rgba;

  Image() = default;
  Image(int w, int h) : width(w), height(h), rgba(static_cast<size_t>(w) * h * 4, 0) {}
  std::uint8_t* pixel(int x, int y) { return &rgba[(static_cast<size_t>(y) * width + x) * 4]; }
  const std::uint8_t* pixel(int x, int y) const { return &rgba[(static_cast<size_t>(y) * width + x) * 4]; }
};

Status writePng(const Image& image, const std::filesystem::path& path);
Result<Image> readPng(const std::filesystem::path& path);

}  // namespace emboss
