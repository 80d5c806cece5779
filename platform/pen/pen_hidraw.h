// The hidraw pen: a live tablet read as raw HID reports through hidapi, decoded by src/input/hid_decode.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "devices/pen.h"
#include "input/hid_decode.h"
#include "util/result.h"

struct hid_device_;

namespace emboss {

struct HidrawDeviceInfo {
  std::string path;  // /dev/hidrawN
  uint16_t vendorId = 0;
  uint16_t productId = 0;
  std::string product;
  std::string manufacturer;
  int interfaceNumber = -1;
  std::string describe() const;  // "256c:006d Huion Tablet (/dev/hidraw3, interface 0)"
};

// The HID devices hidapi sees (one entry per /dev/hidraw node). Fails when hidapi cannot start.
Result<std::vector<HidrawDeviceInfo>> enumerateHidraw();

// The report descriptor of a /dev/hidrawN node: hid_get_report_descriptor where hidapi has it
// (0.14 and later), else /sys/class/hidraw/hidrawN/device/report_descriptor.
Result<std::vector<uint8_t>> readHidrawDescriptor(const std::string& path);

class HidrawPen final : public PenSource {
 public:
  // Opens the node (non-blocking) and decodes its reports with decoder.
  static Result<std::unique_ptr<HidrawPen>> open(const HidrawDeviceInfo& info, std::unique_ptr<PenReportDecoder> decoder);
  ~HidrawPen() override;

  std::string name() const override { return name_; }
  // Reads every pending report (never blocks); false once the device is gone (read error, unplugged).
  bool poll(std::vector<PenSample>& out) override;
  // hidapi hides its descriptor: this source must be polled (fd() is -1).

 private:
  HidrawPen(hid_device_* dev, std::unique_ptr<PenReportDecoder> decoder, std::string name, std::string path);

  hid_device_* dev_ = nullptr;
  std::unique_ptr<PenReportDecoder> decoder_;
  std::string name_;
  std::string path_;
  bool gone_ = false;
};

}  // namespace emboss
