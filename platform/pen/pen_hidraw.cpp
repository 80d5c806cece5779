// The hidraw pen: a live tablet read as raw HID reports through hidapi, decoded by src/input/hid_decode.
#include "pen/pen_hidraw.h"

#include <hidapi/hidapi.h>

#include <cstdio>
#include <fstream>
#include <iterator>
#include <set>

#include "pen/pen_replay.h"

namespace emboss {

namespace {

std::string narrow(const wchar_t* w) {
  std::string s;
  if (!w) return s;
  for (; *w; ++w) s.push_back(*w > 0 && *w < 128 ? static_cast<char>(*w) : '?');
  return s;
}

std::string hex4(uint16_t v) {
  char b[8];
  std::snprintf(b, sizeof b, "%04x", v);
  return b;
}

Status initHidapi() {
  static const int rc = hid_init();
  if (rc != 0) return fail("cannot start hidapi: " + narrow(hid_error(nullptr)));
  return Ok{};
}

}  // namespace

std::string HidrawDeviceInfo::describe() const {
  std::string s = hex4(vendorId) + ":" + hex4(productId);
  const std::string label = manufacturer.empty() ? product : manufacturer + " " + product;
  if (!label.empty()) s += " " + label;
  s += " (" + path;
  if (interfaceNumber >= 0) s += ", interface " + std::to_string(interfaceNumber);
  return s + ")";
}

Result<std::vector<HidrawDeviceInfo>> enumerateHidraw() {
  if (auto st = initHidapi(); !st) return Error{st.error()};
  std::vector<HidrawDeviceInfo> out;
  std::set<std::string> seen;
  hid_device_info* list = hid_enumerate(0, 0);
  for (const hid_device_info* d = list; d; d = d->next) {
    if (!d->path || !seen.insert(d->path).second) continue;  // hidraw lists each top-level usage
    HidrawDeviceInfo info;
    info.path = d->path;
    info.vendorId = d->vendor_id;
    info.productId = d->product_id;
    info.product = narrow(d->product_string);
    info.manufacturer = narrow(d->manufacturer_string);
    info.interfaceNumber = d->interface_number;
    out.push_back(std::move(info));
  }
  hid_free_enumeration(list);
  return out;
}

Result<std::vector<uint8_t>> readHidrawDescriptor(const std::string& path) {
#if defined(HID_API_VERSION) && HID_API_VERSION >= HID_API_MAKE_VERSION(0, 14, 0)
  if (initHidapi()) {
    if (hid_device* dev = hid_open_path(path.c_str())) {
      unsigned char buf[HID_API_MAX_REPORT_DESCRIPTOR_SIZE];
      const int n = hid_get_report_descriptor(dev, buf, sizeof buf);
      hid_close(dev);
      if (n > 0) return std::vector<uint8_t>(buf, buf + n);
    }
  }
#endif
  const std::string node = path.substr(path.find_last_of('/') + 1);
  if (node.rfind("hidraw", 0) != 0) return fail(path + " is not a /dev/hidrawN node");
  const std::string sysfs = "/sys/class/hidraw/" + node + "/device/report_descriptor";
  std::ifstream in(sysfs, std::ios::binary);
  if (!in) return fail("cannot read " + sysfs + " (is " + path + " still plugged in?)");
  std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (bytes.empty()) return fail(sysfs + " is empty: the kernel holds no report descriptor for " + path);
  return bytes;
}

Result<std::unique_ptr<HidrawPen>> HidrawPen::open(const HidrawDeviceInfo& info, std::unique_ptr<PenReportDecoder> decoder) {
  if (auto st = initHidapi(); !st) return Error{st.error()};
  if (!decoder) return fail("no decoder for " + info.describe());
  hid_device* dev = hid_open_path(info.path.c_str());
  if (!dev) {
    return fail("cannot open " + info.describe() + ": " + narrow(hid_error(nullptr)) +
                " (hidraw nodes are usually root-only: add a udev rule, e.g. MODE=\"0660\", GROUP=\"input\")");
  }
  if (hid_set_nonblocking(dev, 1) != 0) {
    const std::string why = narrow(hid_error(dev));
    hid_close(dev);
    return fail("cannot make " + info.path + " non-blocking: " + why);
  }
  const std::string name = "hidraw: " + (info.product.empty() ? info.path : info.product) + " [" + decoder->name() + "]";
  return std::unique_ptr<HidrawPen>(new HidrawPen(dev, std::move(decoder), name, info.path));
}

HidrawPen::HidrawPen(hid_device_* dev, std::unique_ptr<PenReportDecoder> decoder, std::string name, std::string path)
    : dev_(dev), decoder_(std::move(decoder)), name_(std::move(name)), path_(std::move(path)) {}

HidrawPen::~HidrawPen() {
  if (dev_) hid_close(dev_);
}

bool HidrawPen::poll(std::vector<PenSample>& out) {
  if (gone_) return false;
  unsigned char buf[512];
  bool any = false;
  for (int guard = 0; guard < 4096; ++guard) {
    const int n = hid_read(dev_, buf, sizeof buf);
    if (n == 0) break;
    if (n < 0) {
      std::fprintf(stderr, "emboss: %s is gone (%s)\n", path_.c_str(), narrow(hid_error(dev_)).c_str());
      gone_ = true;
      return false;
    }
    any = true;
    if (auto s = decoder_->decode(std::span<const uint8_t>(buf, static_cast<size_t>(n)), monotonicSeconds())) out.push_back(*s);
  }
  if (!any) {
    if (auto s = decoder_->idle(monotonicSeconds())) out.push_back(*s);
  }
  return true;
}

}  // namespace emboss
