// The evdev pen: a live tablet through the kernel's input layer (libevdev), grabbed for the kiosk alone.
#include "pen/pen_evdev.h"

#include <errno.h>
#include <fcntl.h>
#include <libevdev/libevdev.h>
#include <time.h>

#include <algorithm>
#include <cstdio>
#include <cstring>

namespace emboss {

namespace {

std::string openErrorText(const std::filesystem::path& node, int err) {
  if (err == EACCES || err == EPERM) {
    return "cannot open " + node.string() +
           ": permission denied; run the kiosk as a member of group \"input\" or add a udev rule for the tablet";
  }
  return "cannot open " + node.string() + ": " + std::strerror(err);
}

EvdevCaps capsOf(const libevdev* dev) {
  EvdevCaps c;
  if (const char* n = libevdev_get_name(dev)) c.name = n;
  c.vendorId = static_cast<uint16_t>(libevdev_get_id_vendor(dev));
  c.productId = static_cast<uint16_t>(libevdev_get_id_product(dev));
  for (unsigned code = 0; code <= ABS_MAX; ++code) {
    if (!libevdev_has_event_code(dev, EV_ABS, code)) continue;
    const input_absinfo* a = libevdev_get_abs_info(dev, code);
    if (!a) continue;
    c.abs[static_cast<int>(code)] = AbsRange{a->minimum, a->maximum, a->fuzz, a->flat, a->resolution};
  }
  for (unsigned k = BTN_TOOL_PEN; k <= BTN_TOOL_AIRBRUSH; ++k) c.hasToolPen = c.hasToolPen || libevdev_has_event_code(dev, EV_KEY, k);
  c.hasTouch = libevdev_has_event_code(dev, EV_KEY, BTN_TOUCH);
  c.hasStylus = libevdev_has_event_code(dev, EV_KEY, BTN_STYLUS);
  c.hasToolFinger = libevdev_has_event_code(dev, EV_KEY, BTN_TOOL_FINGER);
  c.hasMultitouch = libevdev_has_event_code(dev, EV_ABS, ABS_MT_POSITION_X);
  c.propDirect = libevdev_has_property(dev, INPUT_PROP_DIRECT);
  return c;
}

}  // namespace

void EvdevPen::EvdevFree::operator()(libevdev* d) const { libevdev_free(d); }

std::vector<std::filesystem::path> listEvdevNodes() {
  std::vector<std::pair<int, std::filesystem::path>> nodes;
  std::error_code ec;
  for (std::filesystem::directory_iterator it("/dev/input", ec), end; !ec && it != end; it.increment(ec)) {
    const std::string f = it->path().filename().string();
    if (f.rfind("event", 0) != 0) continue;
    int n = 0;
    if (std::sscanf(f.c_str() + 5, "%d", &n) != 1) continue;
    nodes.emplace_back(n, it->path());
  }
  std::sort(nodes.begin(), nodes.end());
  std::vector<std::filesystem::path> out;
  for (auto& [n, p] : nodes) out.push_back(p);
  return out;
}

Result<EvdevCaps> readEvdevCaps(const std::filesystem::path& node) {
  UniqueFd fd(::open(node.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC));
  if (!fd.valid()) return fail(openErrorText(node, errno));
  libevdev* raw = nullptr;
  const int rc = libevdev_new_from_fd(fd.get(), &raw);
  if (rc < 0) return fail(node.string() + " is not an evdev device: " + std::strerror(-rc));
  EvdevCaps caps = capsOf(raw);
  libevdev_free(raw);
  return caps;
}

Result<std::unique_ptr<EvdevPen>> EvdevPen::open(const std::filesystem::path& node, bool grab) {
  UniqueFd fd(::open(node.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC));
  if (!fd.valid()) return fail(openErrorText(node, errno));
  libevdev* raw = nullptr;
  const int rc = libevdev_new_from_fd(fd.get(), &raw);
  if (rc < 0) return fail(node.string() + " is not an evdev device: " + std::strerror(-rc));
  std::unique_ptr<libevdev, EvdevFree> dev(raw);
  const EvdevCaps caps = capsOf(dev.get());
  if (auto why = evdevUnusableReason(caps)) return fail(node.string() + " (" + caps.name + ") is not a pen tablet: " + *why);
  libevdev_set_clock_id(dev.get(), CLOCK_MONOTONIC);  // time stamps on the kiosk's clock
  if (grab) {
    const int g = libevdev_grab(dev.get(), LIBEVDEV_GRAB);
    if (g < 0) {
      return fail("cannot grab " + node.string() + " (" + caps.name + "): " + std::strerror(-g) +
                  (g == -EBUSY ? "; another program (a desktop session?) holds it" : ""));
    }
  }
  return std::unique_ptr<EvdevPen>(new EvdevPen(std::move(fd), std::move(dev), caps, node.string()));
}

EvdevPen::EvdevPen(UniqueFd fd, std::unique_ptr<libevdev, EvdevFree> dev, const EvdevCaps& caps, std::string path)
    : fd_(std::move(fd)),
      dev_(std::move(dev)),
      state_(caps.abs, caps.hasToolPen, caps.hasTouch),
      name_("evdev: " + caps.name),
      path_(std::move(path)) {}

EvdevPen::~EvdevPen() {
  if (dev_ && !gone_) libevdev_grab(dev_.get(), LIBEVDEV_UNGRAB);
}

bool EvdevPen::poll(std::vector<PenSample>& out) {
  if (gone_) return false;
  input_event ev{};
  auto feed = [&] {
    const double t = static_cast<double>(ev.input_event_sec) + static_cast<double>(ev.input_event_usec) * 1e-6;
    if (auto s = state_.feed(t, ev.type, ev.code, ev.value)) out.push_back(*s);
  };
  for (int guard = 0; guard < 100000; ++guard) {  // a burst larger than this waits for the next poll
    int rc = libevdev_next_event(dev_.get(), LIBEVDEV_READ_FLAG_NORMAL, &ev);
    if (rc == LIBEVDEV_READ_STATUS_SYNC) {
      // Events were dropped: libevdev replays the device's current state, closed by a SYN_REPORT.
      while ((rc = libevdev_next_event(dev_.get(), LIBEVDEV_READ_FLAG_SYNC, &ev)) == LIBEVDEV_READ_STATUS_SYNC) feed();
      if (rc == -EAGAIN) continue;
    } else if (rc == LIBEVDEV_READ_STATUS_SUCCESS) {
      feed();
      continue;
    }
    if (rc == -EAGAIN) return true;
    if (rc == -EINTR) continue;
    if (rc == -ENODEV) {
      std::fprintf(stderr, "emboss: %s (%s) is gone (unplugged?)\n", path_.c_str(), name_.c_str());
    } else {
      std::fprintf(stderr, "emboss: %s: read failed (%s); dropping the tablet\n", path_.c_str(), std::strerror(-rc));
    }
    gone_ = true;
    return false;
  }
  return true;
}

}  // namespace emboss
