// Tests for camera frame decoding: YUYV on known BT.601 values, MJPEG on JPEGs encoded here with libjpeg.
#include <gtest/gtest.h>

#include <cstdio>
#include <vector>

#include <jpeglib.h>

#include "camera/camera_decode.h"

namespace emboss {
namespace {

std::vector<std::uint8_t> yuyv(std::initializer_list<std::array<int, 4>> pairs) {
  std::vector<std::uint8_t> out;
  for (const auto& p : pairs)
    for (int v : p) out.push_back(static_cast<std::uint8_t>(v));
  return out;
}

void expectRgb(const Image& img, int x, int y, int r, int g, int b, int tol = 0) {
  const std::uint8_t* p = img.pixel(x, y);
  EXPECT_NEAR(p[0], r, tol) << "red at " << x << "," << y;
  EXPECT_NEAR(p[1], g, tol) << "green at " << x << "," << y;
  EXPECT_NEAR(p[2], b, tol) << "blue at " << x << "," << y;
  EXPECT_EQ(p[3], 255);
}

TEST(CameraDecode, YuyvVideoLevelsGiveKnownColours) {
  // Y0 U Y1 V: black and white; BT.601 red (81, 90, 240) and mid gray; blue (41, 240, 110) and green (145, 54, 34).
  const auto data = yuyv({{16, 128, 235, 128}, {81, 90, 81, 240}, {126, 128, 126, 128}, {41, 240, 145, 110}});
  auto img = yuyvToRgba(data, 8, 1, 16);
  ASSERT_TRUE(img) << img.error();
  expectRgb(*img, 0, 0, 0, 0, 0);
  expectRgb(*img, 1, 0, 255, 255, 255);
  expectRgb(*img, 2, 0, 255, 0, 0, 1);
  expectRgb(*img, 3, 0, 255, 0, 0, 1);
  expectRgb(*img, 4, 0, 128, 128, 128);
  expectRgb(*img, 6, 0, 0, 0, 255, 2);  // Y 41 with U 240, V 110: blue
}

TEST(CameraDecode, YuyvFullRangeUsesJpegLevels) {
  const auto data = yuyv({{128, 128, 0, 128}, {76, 85, 255, 255}});
  auto img = yuyvToRgba(data, 4, 1, 8, true);
  ASSERT_TRUE(img) << img.error();
  expectRgb(*img, 0, 0, 128, 128, 128);
  expectRgb(*img, 1, 0, 0, 0, 0);
  expectRgb(*img, 2, 0, 255, 0, 0, 2);  // JFIF red
}

TEST(CameraDecode, YuyvHonoursTheLineStride) {
  // Two lines of 2 pixels, each padded to 8 bytes with junk the converter must skip.
  const std::vector<std::uint8_t> data = {16, 128, 16, 128, 9, 9, 9, 9, 235, 128, 235, 128, 9, 9, 9, 9};
  auto img = yuyvToRgba(data, 2, 2, 8);
  ASSERT_TRUE(img) << img.error();
  expectRgb(*img, 1, 0, 0, 0, 0);
  expectRgb(*img, 0, 1, 255, 255, 255);
}

TEST(CameraDecode, YuyvShortFramesAndOddWidthsFail) {
  const std::vector<std::uint8_t> data(10, 128);
  auto shortFrame = yuyvToRgba(data, 4, 2, 8);
  ASSERT_FALSE(shortFrame);
  EXPECT_NE(shortFrame.error().find("short frame: 10 bytes"), std::string::npos) << shortFrame.error();
  EXPECT_FALSE(yuyvToRgba(data, 3, 1, 6));
}

// A 96x64 test card: a gray ramp, with red, green and blue blocks.
Image testCard() {
  Image img(96, 64);
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 96; ++x) {
      std::uint8_t* p = img.pixel(x, y);
      const int v = x * 255 / 95;
      p[0] = p[1] = p[2] = static_cast<std::uint8_t>(v), p[3] = 255;
      if (y >= 32 && x < 32) p[0] = 220, p[1] = 30, p[2] = 30;
      if (y >= 32 && x >= 32 && x < 64) p[0] = 30, p[1] = 200, p[2] = 40;
      if (y >= 32 && x >= 64) p[0] = 20, p[1] = 40, p[2] = 210;
    }
  return img;
}

std::vector<std::uint8_t> encodeJpeg(const Image& img, int quality) {
  jpeg_compress_struct c{};
  jpeg_error_mgr err{};
  c.err = jpeg_std_error(&err);
  jpeg_create_compress(&c);
  unsigned char* buf = nullptr;
  unsigned long size = 0;
  jpeg_mem_dest(&c, &buf, &size);
  c.image_width = static_cast<JDIMENSION>(img.width);
  c.image_height = static_cast<JDIMENSION>(img.height);
  c.input_components = 4;
  c.in_color_space = JCS_EXT_RGBA;
  jpeg_set_defaults(&c);
  jpeg_set_quality(&c, quality, TRUE);
  jpeg_start_compress(&c, TRUE);
  while (c.next_scanline < c.image_height) {
    JSAMPROW row = const_cast<JSAMPROW>(img.pixel(0, static_cast<int>(c.next_scanline)));
    jpeg_write_scanlines(&c, &row, 1);
  }
  jpeg_finish_compress(&c);
  jpeg_destroy_compress(&c);
  std::vector<std::uint8_t> out(buf, buf + size);
  std::free(buf);
  return out;
}

double meanAbsError(const Image& a, const Image& b) {
  double sum = 0;
  for (size_t i = 0; i < a.rgba.size(); ++i) sum += std::abs(int(a.rgba[i]) - int(b.rgba[i]));
  return sum / a.rgba.size();
}

TEST(CameraDecode, MjpegDecodesAJpegEncodedHere) {
  const Image card = testCard();
  auto img = decodeMjpeg(encodeJpeg(card, 95));
  ASSERT_TRUE(img) << img.error();
  ASSERT_EQ(img->width, 96);
  ASSERT_EQ(img->height, 64);
  const double mae = meanAbsError(card, *img);
  std::printf("MJPEG quality 95: mean absolute error %.2f levels\n", mae);
  EXPECT_LT(mae, 3.0);
  expectRgb(*img, 16, 48, 220, 30, 30, 12);
  expectRgb(*img, 80, 48, 20, 40, 210, 12);
}

TEST(CameraDecode, MjpegWithoutHuffmanTablesDecodesAsWebcamsSendIt) {
  // Many UVC cameras leave out the DHT segments and rely on the standard tables.
  const Image card = testCard();
  std::vector<std::uint8_t> jpeg = encodeJpeg(card, 90), stripped;
  for (size_t i = 0; i < jpeg.size();) {
    if (i + 3 < jpeg.size() && jpeg[i] == 0xFF && jpeg[i + 1] == 0xC4) {
      i += 2 + ((jpeg[i + 2] << 8) | jpeg[i + 3]);
      continue;
    }
    if (i + 1 < jpeg.size() && jpeg[i] == 0xFF && jpeg[i + 1] == 0xDA) {  // scan data: copy the rest
      stripped.insert(stripped.end(), jpeg.begin() + static_cast<long>(i), jpeg.end());
      break;
    }
    stripped.push_back(jpeg[i++]);
  }
  ASSERT_LT(stripped.size(), jpeg.size()) << "the encoder wrote no DHT to strip";
  auto img = decodeMjpeg(stripped);
  ASSERT_TRUE(img) << img.error();
  EXPECT_LT(meanAbsError(card, *img), 4.0);
}

TEST(CameraDecode, CorruptMjpegFailsWithoutExiting) {
  auto notJpeg = decodeMjpeg(std::vector<std::uint8_t>{1, 2, 3, 4, 5});
  ASSERT_FALSE(notJpeg);
  EXPECT_NE(notJpeg.error().find("SOI"), std::string::npos) << notJpeg.error();
  std::vector<std::uint8_t> jpeg = encodeJpeg(testCard(), 90);
  std::vector<std::uint8_t> broken(jpeg.begin(), jpeg.begin() + 40);  // a header cut short
  auto cut = decodeMjpeg(broken);
  ASSERT_FALSE(cut);
  EXPECT_NE(cut.error().find("mjpeg: corrupt frame"), std::string::npos) << cut.error();
  // A frame truncated in its scan data (a USB packet lost) still decodes, the rest gray.
  std::vector<std::uint8_t> truncated(jpeg.begin(), jpeg.begin() + static_cast<long>(jpeg.size() * 3 / 4));
  auto partial = decodeMjpeg(truncated);
  EXPECT_TRUE(partial) << partial.error();
}

}  // namespace
}  // namespace emboss
