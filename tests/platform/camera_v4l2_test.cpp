// Tests for the V4L2 camera: clear failures without a camera, and *Hardware* checks that need one.
#include <gtest/gtest.h>

#include "camera/camera_v4l2.h"

namespace emboss {
namespace {

TEST(CameraV4l2, WithoutACameraTheMessageSaysSo) {
  if (!listVideoNodes().empty()) GTEST_SKIP() << "this machine has /dev/video* nodes; see the CameraV4l2Hardware suite";
  auto cam = openV4l2Camera();
  ASSERT_FALSE(cam);
  EXPECT_EQ(cam.error(), "camera: no /dev/video* (no camera on this machine); capture drawing is off until a USB camera is plugged in");
}

TEST(CameraV4l2, AMissingNodeIsNamed) {
  auto cam = openV4l2Camera("/dev/video-none");
  ASSERT_FALSE(cam);
  EXPECT_NE(cam.error().find("/dev/video-none: no such device"), std::string::npos) << cam.error();
}

TEST(CameraV4l2, ANodeThatIsNotACameraIsRefused) {
  auto cam = openV4l2Camera("/dev/null");
  ASSERT_FALSE(cam);
  EXPECT_NE(cam.error().find("/dev/null: not a V4L2 device"), std::string::npos) << cam.error();
}

// Needs a USB (UVC) camera: one still at the negotiated size.
TEST(CameraV4l2Hardware, TakesAStill) {
  if (listVideoNodes().empty()) GTEST_SKIP() << "no /dev/video* on this machine (no camera)";
  V4l2Options o;
  o.width = 640;
  o.height = 480;
  auto cam = V4l2Camera::open("auto", o);
  if (!cam) GTEST_SKIP() << "no usable camera: " << cam.error();
  auto still = (*cam)->capture();
  ASSERT_TRUE(still) << still.error();
  EXPECT_GT(still->width, 0);
  EXPECT_GT(still->height, 0);
  EXPECT_EQ(still->rgba.size(), static_cast<size_t>(still->width) * still->height * 4);
  // A second still from the same open camera (buffers requeued after STREAMOFF).
  auto again = (*cam)->capture();
  ASSERT_TRUE(again) << again.error();
  EXPECT_EQ(again->width, still->width);
}

}  // namespace
}  // namespace emboss
