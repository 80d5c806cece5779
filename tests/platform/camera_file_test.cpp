// Tests for the file camera, the camera's replay twin.
#include <gtest/gtest.h>

#include "camera/camera_file.h"
#include "test_support.h"

namespace emboss {
namespace {

TEST(CameraFile, ReturnsThePngAsTheStill) {
  const auto dir = test::scratchDir("camera_file");
  Image img(8, 4);
  img.pixel(3, 2)[0] = 200;
  img.pixel(3, 2)[3] = 255;
  ASSERT_TRUE(writePng(img, dir / "still.png"));
  auto cam = openFileCamera(dir / "still.png");
  ASSERT_TRUE(cam) << cam.error();
  EXPECT_EQ((*cam)->name(), "file: " + (dir / "still.png").string());
  auto still = (*cam)->capture();
  ASSERT_TRUE(still) << still.error();
  EXPECT_EQ(still->width, 8);
  EXPECT_EQ(still->pixel(3, 2)[0], 200);
}

TEST(CameraFile, AMissingFileFailsAtOpenWithItsPath) {
  auto cam = openFileCamera("/nonexistent/still.png");
  ASSERT_FALSE(cam);
  EXPECT_NE(cam.error().find("/nonexistent/still.png"), std::string::npos) << cam.error();
  EXPECT_NE(cam.error().find("camera (file)"), std::string::npos) << cam.error();
}

}  // namespace
}  // namespace emboss
