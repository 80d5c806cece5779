// HIL: a real USB device through dummy_hcd: a UC-Logic (Huion) tablet emulated as a USB gadget whose
// HID interface is served from user space through FunctionFS, so that the control requests the host
// makes can be answered: the HID report descriptor, SET_IDLE, and the UC-Logic string-descriptor
// handshake (string 200 holds the pen parameters). The kiosk side runs unchanged: libusb enumerates
// the device (enumerateUclogicUsb) and reads string 200 (uclogicHandshake); hidapi finds the
// interface; openFirstTablet picks it with the UC-Logic v2 decoder; pen reports sent from the
// gadget's interrupt endpoint come out as samples; libusb hotplug fires when the UDC is unbound and
// bound again (needs udevd: run-vm.sh --udevd), and the kiosk recovers the tablet.
//
//   hil_usb_gadget            (needs the modules dummy_hcd libcomposite usb_f_fs usbhid hid-generic)
#include <libusb.h>
#include <linux/usb/ch9.h>
#include <linux/usb/functionfs.h>
#include <sys/mount.h>
#include <sys/stat.h>

#include <condition_variable>
#include <deque>

#include "hil_common.h"
#include "input/hid_decode.h"
#include "pen/pen_hidraw.h"
#include "pen/pen_probe.h"
#include "pen/usb_uclogic.h"

namespace fs = std::filesystem;
using emboss::PenSample;

namespace {

constexpr uint16_t kVendor = 0x256c;   // Huion
constexpr uint16_t kProduct = 0x006d;  // the H640P and many others
const fs::path kGadget = "/sys/kernel/config/usb_gadget/hil_uclogic";
const fs::path kFfsMount = "/tmp/hil-ffs-uclogic";

// The pen parameters string 200 answers with (v2: 24-bit maxima): x 50800, y 31750, pressure 8191,
// 5080 lpi. Composite gadgets keep strings as UTF-8 and send UTF-16LE, so the 16 parameter bytes are
// written as 8 UTF-16 code units; none of them may be 0 (it would end the string) or a surrogate.
constexpr int32_t kXMax = 50800, kYMax = 31750, kPMax = 8191, kRes = 5080;

std::vector<uint8_t> paramBytes() {
  return {static_cast<uint8_t>(kXMax), static_cast<uint8_t>(kXMax >> 8), static_cast<uint8_t>(kXMax >> 16),
          static_cast<uint8_t>(kYMax), static_cast<uint8_t>(kYMax >> 8), static_cast<uint8_t>(kYMax >> 16),
          static_cast<uint8_t>(kPMax), static_cast<uint8_t>(kPMax >> 8), static_cast<uint8_t>(kRes), static_cast<uint8_t>(kRes >> 8),
          0x04, 0x00, 0x01, 0x01, 0x01, 0x01};
}

std::string utf8Units(const std::vector<uint8_t>& bytes) {
  std::string s;
  for (size_t i = 0; i + 1 < bytes.size(); i += 2) {
    const unsigned u = bytes[i] | (bytes[i + 1] << 8);
    if (u < 0x80) {
      s += static_cast<char>(u);
    } else if (u < 0x800) {
      s += static_cast<char>(0xC0 | (u >> 6));
      s += static_cast<char>(0x80 | (u & 0x3F));
    } else {
      s += static_cast<char>(0xE0 | (u >> 12));
      s += static_cast<char>(0x80 | ((u >> 6) & 0x3F));
      s += static_cast<char>(0x80 | (u & 0x3F));
    }
  }
  return s;
}

// Interface 0 of the tablet before any driver rewrote it: one vendor-defined input report, ID 8,
// 11 bytes (the v2 pen report); no pen usages, so only the handshake makes it decodable.
const std::vector<uint8_t> kReportDescriptor = {
    0x06, 0x00, 0xFF,  // Usage Page (Vendor 0xFF00)
    0x09, 0x01,        // Usage (1)
    0xA1, 0x01,        // Collection (Application)
    0x85, 0x08,        //   Report ID (8)
    0x75, 0x08,        //   Report Size (8)
    0x95, 0x0B,        //   Report Count (11)
    0x15, 0x00,        //   Logical Minimum (0)
    0x26, 0xFF, 0x00,  //   Logical Maximum (255)
    0x09, 0x01,        //   Usage (1)
    0x81, 0x02,        //   Input (Data, Variable, Absolute)
    0xC0,              // End Collection
};

struct __attribute__((packed)) HidClassDescriptor {
  uint8_t bLength = 9;
  uint8_t bDescriptorType = 0x21;
  uint16_t bcdHID = 0x0111;
  uint8_t bCountryCode = 0;
  uint8_t bNumDescriptors = 1;
  uint8_t bReportType = 0x22;
  uint16_t wDescriptorLength = 0;
};

struct __attribute__((packed)) SpeedDescs {
  usb_interface_descriptor intf;
  HidClassDescriptor hid;
  usb_endpoint_descriptor_no_audio ep;
};

struct __attribute__((packed)) Descriptors {
  usb_functionfs_descs_head_v2 header;
  uint32_t fsCount;
  uint32_t hsCount;
  SpeedDescs fs;
  SpeedDescs hs;
};

// iInterface names the last FunctionFS string: FunctionFS keeps only as many strings as its
// descriptors refer to, and all of them are needed to reach index 200.
SpeedDescs speedDescs(uint8_t interval, uint8_t lastString) {
  SpeedDescs d{};
  d.intf.bLength = sizeof d.intf;
  d.intf.bDescriptorType = USB_DT_INTERFACE;
  d.intf.bNumEndpoints = 1;
  d.intf.bInterfaceClass = USB_CLASS_HID;
  d.intf.bInterfaceSubClass = 1;  // boot interface, mouse protocol: as the real tablets declare
  d.intf.bInterfaceProtocol = 2;
  d.intf.iInterface = lastString;
  d.hid = HidClassDescriptor{};
  d.hid.wDescriptorLength = static_cast<uint16_t>(kReportDescriptor.size());
  d.ep.bLength = sizeof d.ep;
  d.ep.bDescriptorType = USB_DT_ENDPOINT;
  d.ep.bEndpointAddress = 1 | USB_DIR_IN;
  d.ep.bmAttributes = USB_ENDPOINT_XFER_INT;
  d.ep.wMaxPacketSize = 64;
  d.ep.bInterval = interval;
  return d;
}

bool writeAttr(const fs::path& p, const std::string& v) {
  if (hil::writeFile(p, v)) return true;
  hil::note("cannot write %s to %s: %s", v.c_str(), p.c_str(), std::strerror(errno));
  return false;
}

std::string udcName() {
  std::error_code ec;
  for (const auto& e : fs::directory_iterator("/sys/class/udc", ec)) return e.path().filename().string();
  return "";
}

// The gadget: configfs for the device, FunctionFS for its one HID interface.
class Gadget {
 public:
  ~Gadget() { teardown(); }

  bool setup(int stringCount) {
    std::error_code ec;
    fs::create_directories(kGadget / "strings/0x409", ec);
    fs::create_directories(kGadget / "configs/c.1", ec);
    fs::create_directories(kGadget / "functions/ffs.uclogic", ec);
    if (ec) return fail("configfs: " + ec.message() + " (is configfs mounted and libcomposite loaded?)");
    bool ok = writeAttr(kGadget / "idVendor", "0x256c") && writeAttr(kGadget / "idProduct", "0x006d") &&
              writeAttr(kGadget / "bcdDevice", "0x0100") && writeAttr(kGadget / "bcdUSB", "0x0200") &&
              writeAttr(kGadget / "strings/0x409/manufacturer", "HIL") &&
              writeAttr(kGadget / "strings/0x409/product", "HIL UC-Logic tablet") &&
              writeAttr(kGadget / "strings/0x409/serialnumber", "0001") && writeAttr(kGadget / "configs/c.1/MaxPower", "100");
    if (!ok) return fail("configfs attributes");
    fs::create_symlink(kGadget / "functions/ffs.uclogic", kGadget / "configs/c.1/ffs.uclogic", ec);
    fs::create_directories(kFfsMount, ec);
    if (::mount("uclogic", kFfsMount.c_str(), "functionfs", 0, nullptr) != 0) return fail(std::string("mount functionfs: ") + std::strerror(errno));
    mounted_ = true;
    ep0_ = ::open((kFfsMount / "ep0").c_str(), O_RDWR | O_CLOEXEC);
    if (ep0_ < 0) return fail(std::string("open ep0: ") + std::strerror(errno));

    Descriptors d{};
    d.header.magic = FUNCTIONFS_DESCRIPTORS_MAGIC_V2;
    d.header.length = sizeof d;
    d.header.flags = FUNCTIONFS_HAS_FS_DESC | FUNCTIONFS_HAS_HS_DESC;
    d.fsCount = 3;
    d.hsCount = 3;
    d.fs = speedDescs(2, static_cast<uint8_t>(stringCount));  // 2 ms
    d.hs = speedDescs(4, static_cast<uint8_t>(stringCount));  // 2^(4-1) * 125 us = 1 ms
    if (::write(ep0_, &d, sizeof d) != static_cast<ssize_t>(sizeof d)) return fail(std::string("FunctionFS descriptors: ") + std::strerror(errno));

    // Strings: every one is the parameter string, so whichever ID the composite layer hands out
    // first, index 200 (and 100) lands on one of them.
    const std::string param = utf8Units(paramBytes());
    std::string blob;
    auto le32 = [&](uint32_t v) { blob.append(reinterpret_cast<const char*>(&v), 4); };
    le32(FUNCTIONFS_STRINGS_MAGIC);
    le32(0);  // length, patched below
    le32(static_cast<uint32_t>(stringCount));
    le32(1);
    const uint16_t lang = 0x0409;
    blob.append(reinterpret_cast<const char*>(&lang), 2);
    for (int i = 0; i < stringCount; ++i) blob += param + '\0';
    const uint32_t len = static_cast<uint32_t>(blob.size());
    std::memcpy(&blob[4], &len, 4);
    if (::write(ep0_, blob.data(), blob.size()) != static_cast<ssize_t>(blob.size()))
      return fail(std::string("FunctionFS strings: ") + std::strerror(errno));
    ep1_ = ::open((kFfsMount / "ep1").c_str(), O_RDWR | O_CLOEXEC);
    if (ep1_ < 0) return fail(std::string("open ep1: ") + std::strerror(errno));
    stop_ = false;
    control_ = std::thread([this] { controlLoop(); });
    writer_ = std::thread([this] { writeLoop(); });
    return true;
  }

  bool bind() {
    udc_ = udcName();
    if (udc_.empty()) return fail("no UDC in /sys/class/udc (dummy_hcd not loaded?)");
    return writeAttr(kGadget / "UDC", udc_);
  }
  bool unbind() { return writeAttr(kGadget / "UDC", "\n"); }

  // Queues a report for the interrupt endpoint (sent when the host polls it).
  void send(const std::vector<uint8_t>& report) {
    std::lock_guard<std::mutex> lock(mutex_);
    queue_.push_back(report);
    cv_.notify_one();
  }

  void teardown() {
    if (!stop_.exchange(true)) {
      cv_.notify_all();
      if (!udc_.empty()) unbind();
    }
    if (control_.joinable()) control_.join();
    if (writer_.joinable()) writer_.detach();  // may sit in a blocking write; the process ends soon
    if (ep1_ >= 0) ::close(ep1_);
    if (ep0_ >= 0) ::close(ep0_);
    ep0_ = ep1_ = -1;
    if (mounted_) ::umount2(kFfsMount.c_str(), MNT_DETACH);
    mounted_ = false;
    std::error_code ec;
    fs::remove(kGadget / "configs/c.1/ffs.uclogic", ec);
    ::rmdir((kGadget / "configs/c.1/strings/0x409").c_str());
    ::rmdir((kGadget / "configs/c.1").c_str());
    ::rmdir((kGadget / "functions/ffs.uclogic").c_str());
    ::rmdir((kGadget / "strings/0x409").c_str());
    ::rmdir(kGadget.c_str());
  }

  const std::string& error() const { return error_; }
  int setups() const { return setups_; }
  int reportDescriptorRequests() const { return rdescRequests_; }
  bool enabled() const { return enabled_; }

 private:
  bool fail(const std::string& why) {
    error_ = why;
    return false;
  }

  void controlLoop() {
    while (!stop_) {
      pollfd p{ep0_, POLLIN, 0};
      if (::poll(&p, 1, 50) <= 0) continue;
      usb_functionfs_event events[4];
      const ssize_t n = ::read(ep0_, events, sizeof events);
      if (n <= 0) continue;
      for (ssize_t i = 0; i < n / static_cast<ssize_t>(sizeof events[0]); ++i) {
        const auto& e = events[i];
        if (e.type == FUNCTIONFS_ENABLE) enabled_ = true;
        if (e.type == FUNCTIONFS_DISABLE || e.type == FUNCTIONFS_UNBIND) enabled_ = false;
        if (e.type == FUNCTIONFS_SETUP) setup(e.u.setup);
      }
    }
  }

  void setup(const usb_ctrlrequest& r) {
    ++setups_;
    const uint16_t length = r.wLength;
    if (r.bRequestType == (USB_DIR_IN | USB_RECIP_INTERFACE) && r.bRequest == USB_REQ_GET_DESCRIPTOR) {
      if ((r.wValue >> 8) == 0x22) {
        ++rdescRequests_;
        ::write(ep0_, kReportDescriptor.data(), std::min<size_t>(length, kReportDescriptor.size()));
        return;
      }
      if ((r.wValue >> 8) == 0x21) {
        HidClassDescriptor h{};
        h.wDescriptorLength = static_cast<uint16_t>(kReportDescriptor.size());
        ::write(ep0_, &h, std::min<size_t>(length, sizeof h));
        return;
      }
    }
    if (r.bRequestType & USB_DIR_IN) {
      char dummy;
      ::read(ep0_, &dummy, 0);  // reading on an IN request stalls it: not supported
      return;
    }
    std::vector<char> buf(length ? length : 1);
    ::read(ep0_, buf.data(), length);  // SET_IDLE, SET_REPORT, ...: accept
  }

  void writeLoop() {
    for (;;) {
      std::vector<uint8_t> report;
      {
        std::unique_lock<std::mutex> lock(mutex_);
        cv_.wait(lock, [&] { return stop_ || !queue_.empty(); });
        if (stop_) return;
        report = queue_.front();
        queue_.pop_front();
      }
      if (::write(ep1_, report.data(), report.size()) < 0) hil::sleepS(0.01);  // disabled (unbound): dropped
    }
  }

  int ep0_ = -1, ep1_ = -1;
  bool mounted_ = false;
  std::string udc_;
  std::thread control_, writer_;
  std::atomic<bool> stop_{true};
  std::atomic<bool> enabled_{false};
  std::atomic<int> setups_{0}, rdescRequests_{0};
  std::mutex mutex_;
  std::condition_variable cv_;
  std::deque<std::vector<uint8_t>> queue_;
  std::string error_;
};

std::vector<uint8_t> v2Report(double x, double y, double pressure, bool tip) {
  const uint32_t xv = static_cast<uint32_t>(std::lround(x * kXMax));
  const uint32_t yv = static_cast<uint32_t>(std::lround(y * kYMax));
  const uint32_t pv = tip ? static_cast<uint32_t>(std::lround(pressure * kPMax)) : 0;
  return {0x08, static_cast<uint8_t>(0x80 | (tip ? 1 : 0)), static_cast<uint8_t>(xv), static_cast<uint8_t>(xv >> 8),
          static_cast<uint8_t>(yv), static_cast<uint8_t>(yv >> 8), static_cast<uint8_t>(pv), static_cast<uint8_t>(pv >> 8),
          static_cast<uint8_t>(xv >> 16), static_cast<uint8_t>(yv >> 16), 0, 0};
}

// libusb hotplug: counts arrivals and departures of the tablet.
struct Hotplug {
  libusb_context* ctx = nullptr;
  libusb_hotplug_callback_handle handle = 0;
  std::atomic<int> arrived{0}, left{0};
  std::atomic<bool> stop{false};
  std::thread loop;

  static int callback(libusb_context*, libusb_device*, libusb_hotplug_event event, void* self) {
    auto* h = static_cast<Hotplug*>(self);
    if (event == LIBUSB_HOTPLUG_EVENT_DEVICE_ARRIVED) ++h->arrived;
    if (event == LIBUSB_HOTPLUG_EVENT_DEVICE_LEFT) ++h->left;
    return 0;
  }
  bool start() {
    if (libusb_init(&ctx) != 0) return false;
    if (!libusb_has_capability(LIBUSB_CAP_HAS_HOTPLUG)) return false;
    const int rc = libusb_hotplug_register_callback(
        ctx, static_cast<libusb_hotplug_event>(LIBUSB_HOTPLUG_EVENT_DEVICE_ARRIVED | LIBUSB_HOTPLUG_EVENT_DEVICE_LEFT),
        LIBUSB_HOTPLUG_NO_FLAGS, kVendor, kProduct, LIBUSB_HOTPLUG_MATCH_ANY, &Hotplug::callback, this, &handle);
    if (rc != LIBUSB_SUCCESS) return false;
    loop = std::thread([this] {
      while (!stop) {
        timeval tv{0, 50000};
        libusb_handle_events_timeout_completed(ctx, &tv, nullptr);
      }
    });
    return true;
  }
  ~Hotplug() {
    stop = true;
    if (loop.joinable()) loop.join();
    if (ctx) {
      if (handle) libusb_hotplug_deregister_callback(ctx, handle);
      libusb_exit(ctx);
    }
  }
};

// Draws a stroke through the gadget and returns what the pen source read.
std::vector<PenSample> drawStroke(Gadget& g, emboss::PenSource& pen, bool& alive) {
  std::vector<PenSample> live;
  alive = true;
  for (int i = 0; i <= 40; ++i) {
    const double f = i / 40.0;
    const bool tip = i >= 5 && i <= 35;
    g.send(v2Report(0.1 + 0.8 * f, 0.2 + 0.6 * f, tip ? 0.1 + 0.8 * f : 0.0, tip));
    const size_t before = live.size();
    hil::waitFor([&] {
      alive = pen.poll(live) && alive;
      return live.size() > before || !alive;
    }, 0.5, 0.002);
  }
  hil::waitFor([&] {  // the v2 protocol never says "out of range": 100 ms of silence does
    alive = pen.poll(live) && alive;
    return (!live.empty() && !live.back().inRange) || !alive;
  }, 1.0, 0.01);
  return live;
}

void checkStroke(const char* what, const std::vector<PenSample>& live, bool alive) {
  size_t tips = 0;
  bool close = true;
  double lastX = -1;
  for (const auto& s : live) {
    if (!s.tip) continue;
    ++tips;
    close = close && s.x > lastX && s.pressure > 0.05 && s.pressure < 0.95;
    lastX = s.x;
  }
  hil::check(alive && tips >= 28 && close && !live.empty() && !live.back().inRange,
             "%s: the stroke drawn on the gadget comes out of the kiosk's pen source (%zu samples, %zu with the tip down, ends out of range)",
             what, live.size(), tips);
}

std::optional<emboss::UclogicUsbDevice> findTablet() {
  auto list = emboss::enumerateUclogicUsb();
  if (!list) return std::nullopt;
  for (const auto& d : *list)
    if (d.vendorId == kVendor && d.productId == kProduct) return d;
  return std::nullopt;
}

}  // namespace

int main() {
  Gadget g;
  if (!hil::check(g.setup(240), "gadget: configfs + FunctionFS set up %s", g.error().c_str())) return hil::finish("hil_usb_gadget");
  const bool haveUdev = fs::exists("/run/udev/control");
  Hotplug hotplug;
  const bool hotplugOn = haveUdev && hotplug.start();
  if (!hotplugOn) hil::note("libusb hotplug %s: the hotplug checks are skipped", haveUdev ? "did not start" : "needs udevd (run-vm.sh --udevd)");

  if (!hil::check(g.bind(), "gadget: bound to UDC %s %s", udcName().c_str(), g.error().c_str())) return hil::finish("hil_usb_gadget");

  // libusb enumerates it.
  std::optional<emboss::UclogicUsbDevice> dev;
  hil::waitFor([&] { return (dev = findTablet()).has_value(); }, 10.0, 0.05);
  if (!hil::check(dev.has_value(), "libusb: enumerateUclogicUsb lists 256c:006d (%s)", dev ? dev->describe().c_str() : "not found"))
    return hil::finish("hil_usb_gadget");
  if (hotplugOn) hil::check(hil::waitFor([&] { return hotplug.arrived > 0; }, 2.0), "libusb hotplug: ARRIVED on bind");

  // The handshake reads string 200 from the device.
  auto params = emboss::uclogicHandshake(*dev);
  hil::check(params && params->version == 2 && params->xMax == kXMax && params->yMax == kYMax && params->pressureMax == kPMax &&
                 params->resolution == kRes,
             "libusb: uclogicHandshake(%s) reads the pen parameters (%s)", dev->describe().c_str(),
             params ? (std::to_string(params->xMax) + "x" + std::to_string(params->yMax) + ", pressure " + std::to_string(params->pressureMax) +
                       ", " + std::to_string(params->resolution) + " lpi, v" + std::to_string(params->version))
                          .c_str()
                    : params.error().c_str());

  // hidapi sees the interface; the probe chooses the UC-Logic decoder through the handshake.
  std::optional<emboss::HidrawDeviceInfo> info;
  hil::waitFor([&] {
    auto list = emboss::enumerateHidraw();
    if (list)
      for (const auto& d : *list)
        if (d.vendorId == kVendor && d.productId == kProduct) info = d;
    return info.has_value();
  }, 5.0, 0.05);
  hil::check(info && info->interfaceNumber == 0, "hidapi: enumerates the tablet's HID interface (%s)", info ? info->describe().c_str() : "not found");
  hil::check(g.reportDescriptorRequests() > 0, "gadget: the host asked FunctionFS for the report descriptor (%d control requests)", g.setups());
  const auto reports = emboss::probeTablets();
  const auto it = std::find_if(reports.begin(), reports.end(), [&](const emboss::DeviceReport& r) { return info && r.path == info->path; });
  hil::check(it != reports.end() && it->usable && it->detail.find("uc-logic v2") != std::string::npos, "probeTablets: %s (%s)",
             info ? info->path.c_str() : "?", it != reports.end() ? it->detail.c_str() : "not listed");

  auto pen = emboss::openFirstTablet();
  if (hil::check(pen.ok() && (*pen)->name().find("uc-logic v2") != std::string::npos, "openFirstTablet: %s",
                 pen ? (*pen)->name().c_str() : pen.error().c_str())) {
    bool alive = false;
    auto live = drawStroke(g, **pen, alive);
    checkStroke("hidraw", live, alive);
  }

  // Unplug (unbind the UDC): hotplug LEFT, the pen source says it is gone. Replug: back within 2 s.
  const int leftBefore = hotplug.left, arrivedBefore = hotplug.arrived;
  hil::check(g.unbind(), "gadget: unbound from the UDC (unplugged)");
  if (hotplugOn) hil::check(hil::waitFor([&] { return hotplug.left > leftBefore; }, 2.0), "libusb hotplug: LEFT on unbind");
  if (pen) {
    bool gone = false;
    hil::waitFor([&] {
      std::vector<PenSample> out;
      return gone = !(*pen)->poll(out);
    }, 2.0, 0.01);
    hil::check(gone, "the pen source reports the tablet gone");
    pen->reset();
  }
  hil::check(hil::waitFor([&] { return !findTablet(); }, 2.0, 0.05), "libusb: the tablet is no longer enumerated");

  const double t0 = hil::now();
  hil::check(g.bind(), "gadget: bound again (replugged)");
  if (hotplugOn) {
    const bool arrived = hil::waitFor([&] { return hotplug.arrived > arrivedBefore; }, 2.0);
    hil::check(arrived, "libusb hotplug: ARRIVED on rebind, after %.2f s", hil::now() - t0);
  }
  std::unique_ptr<emboss::PenSource> again;
  hil::waitFor([&] {
    auto p = emboss::openFirstTablet();
    if (p && (*p)->name().find("uc-logic v2") != std::string::npos) again = std::move(*p);
    return again != nullptr;
  }, 4.0, 0.1);
  const double took = hil::now() - t0;
  hil::check(again != nullptr && took < 2.0, "openFirstTablet: the replugged tablet is open again (handshake included) %.2f s after the replug",
             took);
  if (again) {
    bool alive = false;
    auto live = drawStroke(g, *again, alive);
    checkStroke("after replug", live, alive);
  }
  again.reset();
  g.teardown();
  return hil::finish("hil_usb_gadget");
}
