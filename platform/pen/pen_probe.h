// Finding the tablet: every evdev and hidraw device with the back end it would get, and opening the first usable one.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "devices/pen.h"
#include "util/result.h"

namespace emboss {

struct DeviceReport {
  std::string backend;  // "evdev" or "hidraw"
  std::string path;     // /dev/input/eventN, /dev/hidrawN
  std::string name;
  uint16_t vendorId = 0;
  uint16_t productId = 0;
  bool usable = false;
  std::string detail;   // how it would be read (ranges, decoder), or why it cannot be used
};

// Every /dev/input/event* node (libevdev) and every hidapi device, tablets or not, with what the
// kiosk would make of it. Empty on a machine without input devices. Never grabs or keeps anything open.
std::vector<DeviceReport> probeTablets();

// Opens the first usable tablet: evdev nodes first (the kernel driver decodes; grabbed
// exclusively), then hidraw devices decoded here (descriptor pens, Wacom fixed-packet models,
// UC-Logic after the libusb handshake). Cheap enough to call every second while no tablet is open;
// each distinct failure is logged once. Fails with a summary when there is none.
Result<std::unique_ptr<PenSource>> openFirstTablet();

}  // namespace emboss
