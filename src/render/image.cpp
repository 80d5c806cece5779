// PNG reading and writing through libpng's simplified API.
#include "render/image.h"

#include <png.h>

#include <cstring>
#include <string>

#include "util/durable_file.h"

namespace emboss {

Status writePng(const Image& image, const std::filesystem::path& path) {
  png_image png;
  std::memset(&png, 0, sizeof png);
  png.version = PNG_IMAGE_VERSION;
  png.width = static_cast<png_uint_32>(image.width);
  png.height = static_cast<png_uint_32>(image.height);
  png.format = PNG_FORMAT_RGBA;
  // Encoded in memory (its size asked first), then written as any file is (writeFileAtomically():
  // a full disk never leaves a truncated picture behind, and a device or a pipe is written in place).
  png_alloc_size_t size = 0;
  if (!png_image_write_to_memory(&png, nullptr, &size, 0, image.rgba.data(), 0, nullptr))
    return fail("cannot write PNG '" + path.string() + "': " + png.message);
  std::string bytes(size, '\0');
  if (!png_image_write_to_memory(&png, bytes.data(), &size, 0, image.rgba.data(), 0, nullptr))
    return fail("cannot write PNG '" + path.string() + "': " + png.message);
  bytes.resize(size);
  return writeFileAtomically(path, bytes);
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
