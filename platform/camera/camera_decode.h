// Camera frame decoding: YUYV (4:2:2) and MJPEG frames from V4L2 to RGBA images.
#pragma once

#include <cstdint>
#include <span>

#include "render/image.h"
#include "util/result.h"

namespace emboss {

// YUYV (Y0 U Y1 V per two pixels) to RGBA, BT.601. fullRange: Y and C use 0..255 (JPEG levels);
// otherwise the usual video levels (Y 16..235, C 16..240) that UVC webcams send. bytesPerLine is the
// driver's line stride (>= 2 * width). Fails when the frame is shorter than the format says.
Result<Image> yuyvToRgba(std::span<const std::uint8_t> data, int width, int height, int bytesPerLine, bool fullRange = false);

// One MJPEG frame (a JPEG, possibly without Huffman tables as many webcams send them) to RGBA, with
// libjpeg-turbo. Fails, without exiting, on data that is not a JPEG or is corrupt beyond a warning.
Result<Image> decodeMjpeg(std::span<const std::uint8_t> data);

}  // namespace emboss
