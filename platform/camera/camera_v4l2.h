// The V4L2 camera: stills from a USB (UVC) camera through mmap streaming, YUYV preferred, MJPEG decoded.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "devices/camera.h"
#include "unique_fd.h"
#include "util/result.h"

namespace emboss {

struct V4l2Options {
  int width = 1280;  // the wanted frame size: the camera's largest size within it is taken
  int height = 720;
  double frameTimeoutS = 2.0;  // poll() time-out per frame
  int warmupFrames = 5;        // frames dropped after STREAMON while exposure and white balance settle
};

// Opens a camera: "auto" takes the first /dev/video* node that captures video with streaming I/O in
// YUYV or MJPEG (metadata, codec and raw-Bayer nodes are skipped, with the reason in the message);
// otherwise a node path such as "/dev/video2". Fails with a message a person can act on ("camera:
// no /dev/video* (no camera on this machine) ...", permission denied, no usable format).
Result<std::unique_ptr<CameraSource>> openV4l2Camera(const std::string& device = "auto");

// The /dev/video* nodes, in numeric order.
std::vector<std::string> listVideoNodes();

class V4l2Camera final : public CameraSource {
 public:
  static Result<std::unique_ptr<V4l2Camera>> open(const std::string& device, const V4l2Options& options = {});
  ~V4l2Camera() override;
  V4l2Camera(const V4l2Camera&) = delete;
  V4l2Camera& operator=(const V4l2Camera&) = delete;

  // "v4l2: /dev/video0 (HD Webcam C270, YUYV 1280x720)".
  std::string name() const override;
  // Streams for one still: STREAMON, drops the warm-up frames, converts the next good one, STREAMOFF.
  // A camera that was unplugged (ENODEV) or stalled is closed with a clear message and reopened on
  // the next call. Takes warmupFrames + 1 frame times (about 0.2 s at 30 fps); blocks until then.
  Result<Image> capture() override;
  // True while the camera is closed after a loss, waiting to be reopened.
  bool lost() const { return !fd_.valid(); }
  // Asks the open node whether it is still there (VIDIOC_QUERYCAP, no streaming): a camera that
  // was unplugged answers ENODEV and is then closed as after a failed capture (lost() becomes
  // true, its buffers are released). False while lost.
  bool present() override;

 private:
  // One mmap'ed driver buffer, unmapped on destruction.
  class Mapping {
   public:
    Mapping(void* addr, size_t length) : addr_(addr), length_(length) {}
    Mapping(Mapping&& o) noexcept;
    Mapping& operator=(Mapping&&) = delete;
    Mapping(const Mapping&) = delete;
    ~Mapping();
    const std::uint8_t* data() const { return static_cast<const std::uint8_t*>(addr_); }
    size_t length() const { return length_; }

   private:
    void* addr_;
    size_t length_;
  };

  V4l2Camera(std::string device, const V4l2Options& options);
  Status openDevice();                  // the configured device, or the first usable one for "auto"
  Status openNode(const std::string& path);
  void closeDevice();
  Error lose(const std::string& why);   // closes the device, logs once, returns the error to pass on
  Result<Image> convert(const std::uint8_t* data, size_t bytes) const;

  std::string device_;  // as asked: "auto" or a path
  V4l2Options options_;
  std::string path_;    // the node in use
  std::string card_;    // the driver's card name
  UniqueFd fd_;
  std::vector<Mapping> buffers_;  // declared after fd_: unmapped before the descriptor closes
  unsigned pixelFormat_ = 0;
  int width_ = 0, height_ = 0, bytesPerLine_ = 0;
  bool fullRange_ = false;
};

}  // namespace emboss
