// Camera frame decoding: integer BT.601 for YUYV, libjpeg-turbo (with a longjmp error handler) for MJPEG.
#include "camera/camera_decode.h"

#include <algorithm>
#include <csetjmp>
#include <cstdio>
#include <string>

#include <jpeglib.h>

namespace emboss {

namespace {

std::uint8_t clamp8(int v) { return static_cast<std::uint8_t>(std::clamp(v, 0, 255)); }

struct JpegError {
  jpeg_error_mgr mgr;
  std::jmp_buf jump;
  char message[JMSG_LENGTH_MAX];
};

[[noreturn]] void onJpegError(j_common_ptr cinfo) {
  auto* err = reinterpret_cast<JpegError*>(cinfo->err);
  (*cinfo->err->format_message)(cinfo, err->message);
  std::longjmp(err->jump, 1);
}

void onJpegMessage(j_common_ptr) {}  // warnings (a truncated frame) are not worth a log line per frame

}  // namespace

Result<Image> yuyvToRgba(std::span<const std::uint8_t> data, int width, int height, int bytesPerLine, bool fullRange) {
  if (width <= 0 || height <= 0 || width % 2 != 0) return fail("yuyv: bad frame size " + std::to_string(width) + "x" + std::to_string(height) + " (the width must be even)");
  if (bytesPerLine < 2 * width) bytesPerLine = 2 * width;
  const size_t need = static_cast<size_t>(bytesPerLine) * (height - 1) + 2 * static_cast<size_t>(width);
  if (data.size() < need)
    return fail("yuyv: short frame: " + std::to_string(data.size()) + " bytes, " + std::to_string(width) + "x" + std::to_string(height) + " needs " + std::to_string(need));
  Image img(width, height);
  for (int y = 0; y < height; ++y) {
    const std::uint8_t* s = data.data() + static_cast<size_t>(y) * bytesPerLine;
    std::uint8_t* d = img.pixel(0, y);
    for (int x = 0; x < width; x += 2, s += 4) {
      const int u = s[1] - 128, v = s[3] - 128;
      for (int k = 0; k < 2; ++k) {
        const int yv = s[k * 2];
        int r, g, b;
        if (fullRange) {  // JPEG (JFIF) levels, 16.16 fixed point
          r = yv + ((91881 * v + 32768) >> 16);
          g = yv - ((22554 * u + 46802 * v + 32768) >> 16);
          b = yv + ((116130 * u + 32768) >> 16);
        } else {  // video levels, 8.8 fixed point
          const int c = 298 * (yv - 16);
          r = (c + 409 * v + 128) >> 8;
          g = (c - 100 * u - 208 * v + 128) >> 8;
          b = (c + 516 * u + 128) >> 8;
        }
        d[0] = clamp8(r), d[1] = clamp8(g), d[2] = clamp8(b), d[3] = 255;
        d += 4;
      }
    }
  }
  return img;
}

namespace {

// Decodes into `out`, which belongs to the caller: nothing local here changes between setjmp and a
// longjmp except libjpeg's own state, which jpeg_destroy_decompress cleans up.
bool decodeInto(std::span<const std::uint8_t> data, Image& out, JpegError& err) {
  jpeg_decompress_struct cinfo{};
  cinfo.err = jpeg_std_error(&err.mgr);
  err.mgr.error_exit = onJpegError;
  err.mgr.output_message = onJpegMessage;
  if (setjmp(err.jump)) {
    jpeg_destroy_decompress(&cinfo);
    return false;
  }
  jpeg_create_decompress(&cinfo);
  jpeg_mem_src(&cinfo, data.data(), static_cast<unsigned long>(data.size()));
  jpeg_read_header(&cinfo, TRUE);  // libjpeg-turbo supplies the standard Huffman tables when a frame has none
  cinfo.out_color_space = JCS_EXT_RGBA;
  jpeg_start_decompress(&cinfo);
  out = Image(static_cast<int>(cinfo.output_width), static_cast<int>(cinfo.output_height));
  while (cinfo.output_scanline < cinfo.output_height) {
    JSAMPROW row = out.pixel(0, static_cast<int>(cinfo.output_scanline));
    jpeg_read_scanlines(&cinfo, &row, 1);
  }
  jpeg_finish_decompress(&cinfo);
  jpeg_destroy_decompress(&cinfo);
  return true;
}

}  // namespace

Result<Image> decodeMjpeg(std::span<const std::uint8_t> data) {
  if (data.size() < 4 || data[0] != 0xFF || data[1] != 0xD8) return fail("mjpeg: the frame does not start with a JPEG SOI marker");
  Image img;
  JpegError err{};
  if (!decodeInto(data, img, err)) return fail(std::string("mjpeg: corrupt frame: ") + err.message);
  return img;
}

}  // namespace emboss
