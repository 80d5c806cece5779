// PNG reading and writing through libpng's simplified API.
#include "render/image.h"

#include <png.h>

#include <cstring>
#include <fstream>

namespace emboss {

Status writePng(const Image& image, const std::filesystem::path& path) {
  png_image png;
  std::memset(&png, 0, sizeof png);
  png.version = PNG_IMAGE_VERSION;
  png.width = static_cast<png_uint_32>(image.width);
  png.height = static_cast<png_uint_32>(image.height);
  png.format = PNG_FORMAT_RGBA;
  // Write to a temporary file first so that a full disk never leaves a truncated picture behind.
  const std::filesystem::path tmp = path.string() + ".part";
  if (!png_image_write_to_file(&png, tmp.c_str(), 0, image.rgba.data(), 0, nullptr)) {
    std::error_code ec;
    std::filesystem::remove(tmp, ec);
    return fail("cannot write PNG '" + path.string() + "': " + png.message);
  }
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) return fail("cannot write PNG '" + path.string() + "': " + ec.message());
  return Ok{};
}

Result<Image> readPng(const std::filesystem::path& path) {
  png_image png;
  std::memset(&png, 0, sizeof png);
  png.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_file(&png, path.c_str())) {
    return fail("cannot read PNG '" + path.string() + "': " + png.message);
  }
  png.format = PNG_FORMAT_RGBA;
  Image image(static_cast<int>(png.width), static_cast<int>(png.height));
  if (!png_image_finish_read(&png, nullptr, image.rgba.data(), 0, nullptr)) {
    return fail("cannot decode PNG '" + path.string() + "': " + png.message);
  }
  return image;
}

}  // namespace emboss
