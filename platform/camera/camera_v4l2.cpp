// The V4L2 camera: QUERYCAP, format negotiation, mmap buffers, poll() with time-outs, loss and reopening.
#include "camera/camera_v4l2.h"

#include <fcntl.h>
#include <linux/videodev2.h>
#include <poll.h>
#include <sys/ioctl.h>
#include <sys/mman.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <span>
#include <utility>

#include "camera/camera_decode.h"
#include "platform_util.h"

namespace emboss {

namespace {

// ioctl, retried when a signal interrupts it; -errno on failure.
int xioctl(int fd, unsigned long request, void* arg) {
  int rc;
  do rc = ::ioctl(fd, request, arg);
  while (rc < 0 && errno == EINTR);
  return rc < 0 ? -errno : rc;
}

std::string fourcc(unsigned f) {
  std::string s;
  for (int i = 0; i < 4; ++i) {
    const char c = static_cast<char>((f >> (8 * i)) & 0xFF);
    s += (c >= 32 && c < 127) ? c : '?';
  }
  while (!s.empty() && s.back() == ' ') s.pop_back();
  return s;
}

bool isLoss(int err) { return err == ENODEV || err == ENXIO || err == EIO; }

constexpr unsigned kBufferCount = 4;
constexpr int kMaxBadFrames = 5;

}  // namespace

std::vector<std::string> listVideoNodes() {
  std::vector<std::pair<int, std::string>> found;
  std::error_code ec;
  for (const auto& e : std::filesystem::directory_iterator("/dev", ec)) {
    const std::string name = e.path().filename().string();
    if (name.rfind("video", 0) != 0 || name.size() == 5) continue;
    const std::string num = name.substr(5);
    if (!std::all_of(num.begin(), num.end(), [](char c) { return c >= '0' && c <= '9'; })) continue;
    found.emplace_back(std::stoi(num), e.path().string());
  }
  std::sort(found.begin(), found.end());
  std::vector<std::string> out;
  for (auto& [n, path] : found) out.push_back(std::move(path));
  return out;
}

V4l2Camera::Mapping::Mapping(Mapping&& o) noexcept : addr_(std::exchange(o.addr_, MAP_FAILED)), length_(o.length_) {}

V4l2Camera::Mapping::~Mapping() {
  if (addr_ != MAP_FAILED) ::munmap(addr_, length_);
}

V4l2Camera::V4l2Camera(std::string device, const V4l2Options& options) : device_(std::move(device)), options_(options) {}

V4l2Camera::~V4l2Camera() { closeDevice(); }

Result<std::unique_ptr<V4l2Camera>> V4l2Camera::open(const std::string& device, const V4l2Options& options) {
  std::unique_ptr<V4l2Camera> cam(new V4l2Camera(device.empty() ? "auto" : device, options));
  if (auto s = cam->openDevice(); !s) return fail(s.error());
  return cam;
}

Result<std::unique_ptr<CameraSource>> openV4l2Camera(const std::string& device) {
  auto cam = V4l2Camera::open(device);
  if (!cam) return fail(cam.error());
  return std::unique_ptr<CameraSource>(std::move(*cam));
}

std::string V4l2Camera::name() const {
  if (!fd_.valid()) return "v4l2: " + (path_.empty() ? device_ : path_) + " (lost; reopened on the next capture)";
  return "v4l2: " + path_ + " (" + card_ + ", " + fourcc(pixelFormat_) + " " + std::to_string(width_) + "x" + std::to_string(height_) + ")";
}

Status V4l2Camera::openDevice() {
  if (device_ != "auto") return openNode(device_);
  const auto nodes = listVideoNodes();
  if (nodes.empty()) return fail("camera: no /dev/video* (no camera on this machine); capture drawing is off until a USB camera is plugged in");
  std::string reasons;
  for (const auto& node : nodes) {
    auto s = openNode(node);
    if (s) return s;
    reasons += (reasons.empty() ? "" : "; ") + s.error();
  }
  return fail("camera: no usable camera: " + reasons);
}

Status V4l2Camera::openNode(const std::string& path) {
  closeDevice();
  UniqueFd fd(::open(path.c_str(), O_RDWR | O_NONBLOCK | O_CLOEXEC));
  if (!fd.valid()) {
    const int err = errno;
    if (err == EACCES || err == EPERM)
      return fail(path + ": permission denied; install systemd/99-emboss-kiosk.rules and add the kiosk user to group 'emboss' (docs/hardware.md)");
    if (err == ENOENT) return fail(path + ": no such device (unplugged?)");
    return fail(path + ": cannot open: " + std::strerror(err));
  }
  v4l2_capability cap{};
  if (int rc = xioctl(fd.get(), VIDIOC_QUERYCAP, &cap); rc < 0) return fail(path + ": not a V4L2 device (VIDIOC_QUERYCAP: " + std::strerror(-rc) + ")");
  const unsigned caps = (cap.capabilities & V4L2_CAP_DEVICE_CAPS) ? cap.device_caps : cap.capabilities;
  const std::string card(reinterpret_cast<const char*>(cap.card), strnlen(reinterpret_cast<const char*>(cap.card), sizeof cap.card));
  if (!(caps & V4L2_CAP_VIDEO_CAPTURE)) return fail(path + " (" + card + "): not a video capture node (metadata, output or codec)");
  if (!(caps & V4L2_CAP_STREAMING)) return fail(path + " (" + card + "): no streaming I/O");

  // Formats: YUYV converts exactly and cheaply; MJPEG is what most cameras offer at large sizes.
  std::vector<unsigned> formats;
  for (unsigned i = 0;; ++i) {
    v4l2_fmtdesc d{};
    d.index = i;
    d.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    if (xioctl(fd.get(), VIDIOC_ENUM_FMT, &d) < 0) break;
    formats.push_back(d.pixelformat);
  }
  unsigned want = 0;
  if (std::find(formats.begin(), formats.end(), V4L2_PIX_FMT_YUYV) != formats.end()) want = V4L2_PIX_FMT_YUYV;
  else if (std::find(formats.begin(), formats.end(), V4L2_PIX_FMT_MJPEG) != formats.end()) want = V4L2_PIX_FMT_MJPEG;
  if (!want) {
    std::string offered;
    for (unsigned f : formats) offered += (offered.empty() ? "" : ", ") + fourcc(f);
    return fail(path + " (" + card + "): offers neither YUYV nor MJPEG (offers " + (offered.empty() ? "nothing" : offered) +
                "); a Raspberry Pi camera module needs libcamera, use a USB (UVC) camera");
  }

  // The largest discrete size within the wanted one (or the smallest offered when none fits).
  unsigned w = static_cast<unsigned>(options_.width), h = static_cast<unsigned>(options_.height);
  {
    unsigned bestW = 0, bestH = 0, smallW = 0, smallH = 0;
    for (unsigned i = 0;; ++i) {
      v4l2_frmsizeenum s{};
      s.index = i;
      s.pixel_format = want;
      if (xioctl(fd.get(), VIDIOC_ENUM_FRAMESIZES, &s) < 0) break;
      if (s.type != V4L2_FRMSIZE_TYPE_DISCRETE) {  // stepwise or continuous: ask, the driver rounds
        bestW = std::clamp(w, s.stepwise.min_width, s.stepwise.max_width);
        bestH = std::clamp(h, s.stepwise.min_height, s.stepwise.max_height);
        break;
      }
      const unsigned dw = s.discrete.width, dh = s.discrete.height;
      if (dw <= w && dh <= h && dw * dh > bestW * bestH) bestW = dw, bestH = dh;
      if (smallW == 0 || dw * dh < smallW * smallH) smallW = dw, smallH = dh;
    }
    if (bestW) w = bestW, h = bestH;
    else if (smallW) w = smallW, h = smallH;
  }
  v4l2_format fmt{};
  fmt.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  fmt.fmt.pix.width = w;
  fmt.fmt.pix.height = h;
  fmt.fmt.pix.pixelformat = want;
  fmt.fmt.pix.field = V4L2_FIELD_NONE;
  if (int rc = xioctl(fd.get(), VIDIOC_S_FMT, &fmt); rc < 0) {
    if (rc == -EBUSY) return fail(path + " (" + card + "): busy: another program is streaming from it");
    return fail(path + " (" + card + "): cannot set " + fourcc(want) + " " + std::to_string(w) + "x" + std::to_string(h) + ": " + std::strerror(-rc));
  }
  if (fmt.fmt.pix.pixelformat != want) return fail(path + " (" + card + "): the driver refused " + fourcc(want) + " (gave " + fourcc(fmt.fmt.pix.pixelformat) + ")");

  v4l2_requestbuffers req{};
  req.count = kBufferCount;
  req.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  req.memory = V4L2_MEMORY_MMAP;
  if (int rc = xioctl(fd.get(), VIDIOC_REQBUFS, &req); rc < 0) {
    if (rc == -EBUSY) return fail(path + " (" + card + "): busy: another program is streaming from it");
    return fail(path + " (" + card + "): no mmap streaming (VIDIOC_REQBUFS: " + std::strerror(-rc) + ")");
  }
  if (req.count < 2) return fail(path + " (" + card + "): the driver gave " + std::to_string(req.count) + " buffer(s); at least 2 are needed");
  std::vector<Mapping> buffers;
  for (unsigned i = 0; i < req.count; ++i) {
    v4l2_buffer b{};
    b.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    b.memory = V4L2_MEMORY_MMAP;
    b.index = i;
    if (int rc = xioctl(fd.get(), VIDIOC_QUERYBUF, &b); rc < 0) return fail(path + ": VIDIOC_QUERYBUF: " + std::strerror(-rc));
    void* addr = ::mmap(nullptr, b.length, PROT_READ | PROT_WRITE, MAP_SHARED, fd.get(), b.m.offset);
    if (addr == MAP_FAILED) return fail(path + ": cannot map a frame buffer: " + std::strerror(errno));
    buffers.emplace_back(addr, b.length);
  }

  fd_ = std::move(fd);
  buffers_ = std::move(buffers);
  path_ = path;
  card_ = card;
  pixelFormat_ = want;
  width_ = static_cast<int>(fmt.fmt.pix.width);
  height_ = static_cast<int>(fmt.fmt.pix.height);
  bytesPerLine_ = static_cast<int>(fmt.fmt.pix.bytesperline);
  fullRange_ = fmt.fmt.pix.quantization == V4L2_QUANTIZATION_FULL_RANGE;
  return Ok{};
}

void V4l2Camera::closeDevice() {
  buffers_.clear();  // unmap before the descriptor closes; closing frees the driver's buffers
  fd_.reset();
}

Error V4l2Camera::lose(const std::string& why) {
  const std::string path = path_;
  closeDevice();
  const std::string message = "camera: " + path + " " + why + "; it is reopened on the next capture";
  logOnce(message);
  return fail(message);
}

bool V4l2Camera::present() {
  if (!fd_.valid()) return false;
  v4l2_capability cap{};
  const int rc = xioctl(fd_.get(), VIDIOC_QUERYCAP, &cap);
  if (rc < 0 && isLoss(-rc)) {
    lose("is gone (unplugged?)");
    return false;
  }
  return true;  // another error (never seen) is not taken for a loss: the next capture tells
}

Result<Image> V4l2Camera::convert(const std::uint8_t* data, size_t bytes) const {
  if (pixelFormat_ == V4L2_PIX_FMT_YUYV) return yuyvToRgba(std::span(data, bytes), width_, height_, bytesPerLine_, fullRange_);
  return decodeMjpeg(std::span(data, bytes));
}

Result<Image> V4l2Camera::capture() {
  if (!fd_.valid()) {
    if (auto s = openDevice(); !s) return fail(s.error());
    logOnce("camera: reopened " + name());
  }
  const int fd = fd_.get();
  for (unsigned i = 0; i < buffers_.size(); ++i) {
    v4l2_buffer b{};
    b.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    b.memory = V4L2_MEMORY_MMAP;
    b.index = i;
    if (int rc = xioctl(fd, VIDIOC_QBUF, &b); rc < 0) {
      if (isLoss(-rc)) return lose("is gone (unplugged?)");
      return lose(std::string("cannot queue a buffer (") + std::strerror(-rc) + ")");
    }
  }
  int type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  if (int rc = xioctl(fd, VIDIOC_STREAMON, &type); rc < 0) {
    if (isLoss(-rc)) return lose("is gone (unplugged?)");
    return lose(std::string("will not stream (") + std::strerror(-rc) + "; in use by another program?)");
  }
  // STREAMOFF on every way out while the device is open: it also takes back the queued buffers.
  struct StreamOff {
    V4l2Camera* cam;
    ~StreamOff() {
      int t = V4L2_BUF_TYPE_VIDEO_CAPTURE;
      if (cam->fd_.valid()) xioctl(cam->fd_.get(), VIDIOC_STREAMOFF, &t);
    }
  } streamOff{this};

  int frames = 0, bad = 0;
  std::string lastBad;
  for (;;) {
    const double deadline = monotonicSeconds() + options_.frameTimeoutS;
    v4l2_buffer b{};
    for (;;) {
      const double left = deadline - monotonicSeconds();
      if (left <= 0) {
        char t[32];
        std::snprintf(t, sizeof t, "%.1f", options_.frameTimeoutS);
        return lose(std::string("gave no frame within ") + t + " s (stalled, or the USB bus is short of bandwidth)");
      }
      pollfd p{fd, POLLIN, 0};
      const int n = ::poll(&p, 1, static_cast<int>(left * 1000) + 1);
      if (n < 0 && errno != EINTR) return lose(std::string("poll failed (") + std::strerror(errno) + ")");
      if (n <= 0) continue;
      b = v4l2_buffer{};
      b.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
      b.memory = V4L2_MEMORY_MMAP;
      const int rc = xioctl(fd, VIDIOC_DQBUF, &b);
      if (rc == -EAGAIN) continue;
      if (rc < 0) {
        if (isLoss(-rc) || (p.revents & POLLERR)) return lose("is gone (unplugged?)");
        return lose(std::string("cannot dequeue a frame (") + std::strerror(-rc) + ")");
      }
      break;
    }
    const bool corrupt = (b.flags & V4L2_BUF_FLAG_ERROR) != 0 || b.index >= buffers_.size();
    if (!corrupt && frames >= options_.warmupFrames) {
      const size_t used = b.bytesused ? b.bytesused : buffers_[b.index].length();
      auto img = convert(buffers_[b.index].data(), std::min(used, buffers_[b.index].length()));
      if (img) return img;
      lastBad = img.error();
      ++bad;
    } else if (corrupt) {
      lastBad = "the driver flagged a frame as corrupt";
      ++bad;
    }
    ++frames;
    if (bad > kMaxBadFrames) return fail("camera: " + path_ + ": " + std::to_string(bad) + " bad frames in a row (" + lastBad + ")");
    if (b.index < buffers_.size()) {
      if (int rc = xioctl(fd, VIDIOC_QBUF, &b); rc < 0) {
        if (isLoss(-rc)) return lose("is gone (unplugged?)");
        return lose(std::string("cannot requeue a buffer (") + std::strerror(-rc) + ")");
      }
    }
  }
}

}  // namespace emboss
