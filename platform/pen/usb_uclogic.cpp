// UC-Logic tablets over libusb: finding them and the string-descriptor handshake (full-resolution mode, true maxima).
#include "pen/usb_uclogic.h"

#include <libusb.h>

#include <cstdio>
#include <memory>
#include <optional>

namespace emboss {

namespace {

constexpr uint16_t kLangEnUs = 0x0409;

struct ContextFree {
  void operator()(libusb_context* c) const { libusb_exit(c); }
};
struct HandleClose {
  void operator()(libusb_device_handle* h) const { libusb_close(h); }
};
struct ListFree {
  void operator()(libusb_device** l) const { libusb_free_device_list(l, 1); }
};
using Context = std::unique_ptr<libusb_context, ContextFree>;
using Handle = std::unique_ptr<libusb_device_handle, HandleClose>;
using DeviceList = std::unique_ptr<libusb_device*, ListFree>;

Result<Context> makeContext() {
  libusb_context* ctx = nullptr;
  const int rc = libusb_init(&ctx);
  if (rc != 0) return fail(std::string("cannot start libusb: ") + libusb_strerror(rc));
  return Context(ctx);
}

std::string hex4(uint16_t v) {
  char b[8];
  std::snprintf(b, sizeof b, "%04x", v);
  return b;
}

// Calls f(device, descriptor) for each UC-Logic device; stops when f returns true.
template <class F>
Status forEachUclogic(libusb_context* ctx, F&& f) {
  libusb_device** raw = nullptr;
  const ssize_t n = libusb_get_device_list(ctx, &raw);
  if (n < 0) return fail(std::string("cannot list USB devices: ") + libusb_strerror(static_cast<int>(n)));
  DeviceList list(raw);
  for (ssize_t i = 0; i < n; ++i) {
    libusb_device_descriptor d{};
    if (libusb_get_device_descriptor(raw[i], &d) != 0) continue;
    if (!isUclogicVendor(d.idVendor)) continue;
    if (f(raw[i], d)) break;
  }
  return Ok{};
}

Result<UclogicPenParams> handshakeOn(libusb_device* dev, const UclogicUsbDevice& info) {
  libusb_device_handle* raw = nullptr;
  const int rc = libusb_open(dev, &raw);
  if (rc == LIBUSB_ERROR_ACCESS) {
    return fail("permission denied opening " + info.describe() +
                " for the UC-Logic handshake; add a udev rule giving the kiosk user access to the tablet");
  }
  if (rc != 0) return fail("cannot open " + info.describe() + ": " + libusb_strerror(rc));
  Handle handle(raw);
  std::string why;
  for (const uint8_t index : {kUclogicV2StringIndex, kUclogicV1StringIndex}) {
    unsigned char buf[32] = {};
    const int len = index == kUclogicV2StringIndex ? 18 : 12;
    const int got = libusb_get_string_descriptor(handle.get(), index, kLangEnUs, buf, len);
    if (got < 0) {
      why += (why.empty() ? "" : "; ") + std::string("string ") + std::to_string(index) + ": " +
             (got == LIBUSB_ERROR_PIPE ? "not present" : libusb_strerror(got));
      continue;
    }
    auto params = parseUclogicPenString(index, std::span<const uint8_t>(buf, static_cast<size_t>(got)));
    if (params) return params;
    why += (why.empty() ? "" : "; ") + params.error();
  }
  return fail(info.describe() + " did not answer the UC-Logic handshake (" + why + ")");
}

}  // namespace

std::string UclogicUsbDevice::describe() const {
  return hex4(vendorId) + ":" + hex4(productId) + " on bus " + std::to_string(bus) + " address " + std::to_string(address);
}

Result<std::vector<UclogicUsbDevice>> enumerateUclogicUsb() {
  auto ctx = makeContext();
  if (!ctx) return Error{ctx.error()};
  std::vector<UclogicUsbDevice> out;
  auto st = forEachUclogic(ctx->get(), [&](libusb_device* dev, const libusb_device_descriptor& d) {
    out.push_back(UclogicUsbDevice{d.idVendor, d.idProduct, libusb_get_bus_number(dev), libusb_get_device_address(dev)});
    return false;
  });
  if (!st) return Error{st.error()};
  return out;
}

Result<UclogicPenParams> uclogicHandshake(const UclogicUsbDevice& device) {
  auto ctx = makeContext();
  if (!ctx) return Error{ctx.error()};
  std::optional<Result<UclogicPenParams>> result;
  auto st = forEachUclogic(ctx->get(), [&](libusb_device* dev, const libusb_device_descriptor& d) {
    if (d.idVendor != device.vendorId || d.idProduct != device.productId || libusb_get_bus_number(dev) != device.bus ||
        libusb_get_device_address(dev) != device.address) {
      return false;
    }
    result = handshakeOn(dev, device);
    return true;
  });
  if (!st) return Error{st.error()};
  if (!result) return fail(device.describe() + " is not connected (unplugged?)");
  return std::move(*result);
}

Result<UclogicPenParams> uclogicHandshake(uint16_t vendorId, uint16_t productId) {
  if (!isUclogicVendor(vendorId)) return fail(hex4(vendorId) + " is not a UC-Logic vendor (256c, 28bd, 5543)");
  auto ctx = makeContext();
  if (!ctx) return Error{ctx.error()};
  std::optional<Result<UclogicPenParams>> result;
  auto st = forEachUclogic(ctx->get(), [&](libusb_device* dev, const libusb_device_descriptor& d) {
    if (d.idVendor != vendorId || d.idProduct != productId) return false;
    result = handshakeOn(dev, UclogicUsbDevice{d.idVendor, d.idProduct, libusb_get_bus_number(dev), libusb_get_device_address(dev)});
    return true;
  });
  if (!st) return Error{st.error()};
  if (!result) return fail("no USB device " + hex4(vendorId) + ":" + hex4(productId) + " is connected");
  return std::move(*result);
}

}  // namespace emboss
