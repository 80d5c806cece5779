// HIL: the V4L2 camera back end against vivid, the kernel's virtual video test driver: format
// negotiation (the largest size within the wanted one, YUYV), mmap streaming, a still with the test
// pattern in it, node selection ("auto" skips output and metadata nodes), and the camera being
// removed (the vivid platform device unbound) while idle and while streaming, then coming back.
//
//   hil_camera_vivid          (needs the module vivid)
#include <set>

#include "camera/camera_v4l2.h"
#include "hil_common.h"

namespace fs = std::filesystem;

namespace {

const fs::path kDriver = "/sys/bus/platform/drivers/vivid";

// /dev/videoN of vivid's node with this sysfs name suffix ("vid-cap", "vid-out").
std::string vividNode(const std::string& kind) {
  std::error_code ec;
  std::vector<std::string> found;
  for (const auto& e : fs::directory_iterator("/sys/class/video4linux", ec)) {
    const auto name = hil::readFile(e.path() / "name");
    const std::string f = e.path().filename().string();
    if (name && hil::trim(*name).find("vivid") != std::string::npos && hil::trim(*name).find(kind) != std::string::npos &&
        f.rfind("video", 0) == 0)
      found.push_back("/dev/" + f);
  }
  std::sort(found.begin(), found.end());
  return found.empty() ? "" : found.front();
}

std::string vividDevice() {
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(kDriver, ec))
    if (e.path().filename().string().rfind("vivid.", 0) == 0) return e.path().filename().string();
  return "";
}

// Distinct colours along the middle row, and whether the image is opaque.
std::pair<size_t, bool> looksLikeAPicture(const emboss::Image& img) {
  std::set<uint32_t> colours;
  bool opaque = true;
  const int y = img.height / 2;
  for (int x = 0; x < img.width; x += 4) {
    const uint8_t* p = img.pixel(x, y);
    colours.insert((p[0] / 32) << 16 | (p[1] / 32) << 8 | (p[2] / 32));
    opaque = opaque && p[3] == 255;
  }
  return {colours.size(), opaque};
}

}  // namespace

int main() {
  std::string capNode;
  hil::waitFor([&] { return !(capNode = vividNode("vid-cap")).empty(); }, 5.0, 0.05);
  const std::string dev = vividDevice();
  if (!hil::check(!capNode.empty() && !dev.empty(), "vivid is loaded: capture node %s, platform device %s", capNode.c_str(), dev.c_str()))
    return hil::finish("hil_camera_vivid");
  const auto nodes = emboss::listVideoNodes();
  hil::note("video nodes: %zu (capture node %s)", nodes.size(), capNode.c_str());

  // A node that is not a capture node is refused with the reason.
  const std::string outNode = vividNode("vid-out");
  if (!outNode.empty()) {
    auto out = emboss::V4l2Camera::open(outNode);
    hil::check(!out && out.error().find("not a video capture node") != std::string::npos, "%s (video output) is refused (%s)", outNode.c_str(),
               out ? "it opened" : out.error().c_str());
  }

  // The factory, as the kiosk calls it: "auto", 1280x720 wanted.
  {
    const double t0 = hil::now();
    auto cam = emboss::openV4l2Camera("auto");
    if (hil::check(cam.ok(), "openV4l2Camera(auto): %s", cam ? (*cam)->name().c_str() : cam.error().c_str())) {
      hil::check((*cam)->name().find(capNode) != std::string::npos && (*cam)->name().find("YUYV 1280x720") != std::string::npos,
                 "it negotiated YUYV 1280x720 on %s", capNode.c_str());
      auto img = (*cam)->capture();
      if (hil::check(img.ok(), "capture() (%s, %.1f s)", img ? "ok" : img.error().c_str(), hil::now() - t0)) {
        const auto [colours, opaque] = looksLikeAPicture(*img);
        hil::check(img->width == 1280 && img->height == 720 && colours >= 6 && opaque,
                   "the still is 1280x720 RGBA with vivid's colour bars in it (%dx%d, %zu colours along a row)", img->width, img->height,
                   colours);
        const auto png = fs::temp_directory_path() / "hil-vivid.png";
        hil::check(static_cast<bool>(emboss::writePng(*img, png)), "the still saves as PNG (%s)", png.c_str());
      }
    }
  }

  emboss::V4l2Options small;
  small.width = 320;
  small.height = 240;
  small.warmupFrames = 1;
  auto opened = emboss::V4l2Camera::open(capNode, small);
  if (!hil::check(opened.ok(), "V4l2Camera::open(%s, 320x240 wanted): %s", capNode.c_str(), opened ? (*opened)->name().c_str() : opened.error().c_str()))
    return hil::finish("hil_camera_vivid");
  auto& cam = **opened;
  hil::check(cam.name().find("320x180") != std::string::npos, "the largest size within 320x240 is taken (%s)", cam.name().c_str());
  int good = 0;
  for (int i = 0; i < 3; ++i) good += cam.capture().ok();
  hil::check(good == 3, "three stills in a row (%d good)", good);

  // Removed while idle: the next capture fails cleanly, the camera is marked lost; back when rebound.
  hil::check(hil::writeFile(kDriver / "unbind", dev), "unbind %s (the camera is unplugged)", dev.c_str());
  auto lost = cam.capture();
  hil::check(!lost && cam.lost(), "capture() after the removal fails and marks the camera lost (%s)", lost ? "it succeeded" : lost.error().c_str());
  auto still = cam.capture();
  hil::check(!still, "capture() while the camera is away keeps failing (%s)", still ? "it succeeded" : still.error().c_str());
  hil::check(hil::writeFile(kDriver / "bind", dev), "bind %s again (replugged)", dev.c_str());
  bool back = false;
  const double t0 = hil::now();
  hil::waitFor([&] { return back = cam.capture().ok(); }, 8.0, 0.2);
  hil::check(back && !cam.lost(), "the camera reopens itself on a later capture (%.1f s after the replug): %s", hil::now() - t0, cam.name().c_str());

  // Removed while streaming: the capture in progress ends with an error, promptly. (One camera
  // object at a time: the first holds the driver's buffers while open.)
  opened->reset();
  emboss::V4l2Options slow = small;
  slow.warmupFrames = 100;  // about 20 s of frames: the removal comes first
  auto streaming = emboss::V4l2Camera::open(capNode, slow);
  if (hil::check(streaming.ok(), "a camera object for a long capture (%s)", streaming ? "ok" : streaming.error().c_str())) {
    std::optional<emboss::Result<emboss::Image>> result;
    double ended = 0;
    std::thread worker([&] {
      result = (*streaming)->capture();
      ended = hil::now();
    });
    hil::sleepS(1.0);
    const double removed = hil::now();
    hil::writeFile(kDriver / "unbind", dev);
    worker.join();
    hil::check(result && !result->ok() && ended - removed < slow.frameTimeoutS + 1.0,
               "a capture in progress ends with an error %.2f s after the removal (%s)", ended - removed,
               result && !result->ok() ? result->error().c_str() : "it succeeded");
    hil::writeFile(kDriver / "bind", dev);
    bool again = false;
    auto after = emboss::V4l2Camera::open(capNode, small);
    hil::waitFor([&] {
      if (!after) after = emboss::V4l2Camera::open(capNode, small);
      return again = after && (*after)->capture().ok();
    }, 8.0, 0.2);
    hil::check(again, "and after the replug stills come again");
  }
  return hil::finish("hil_camera_vivid");
}
