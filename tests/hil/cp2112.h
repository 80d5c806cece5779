// The CP2112 USB-HID to SMBus/GPIO bridge emulated over uhid, so that the kernel's hid-cp2112
// driver registers a real gpiochip ("cp2112_gpio", 8 lines) whose pins a test moves. Shared by the
// GPIO back-end test and the kiosk-with-buttons test. The driver polls the pin levels every 10
// jiffies (40 ms at HZ=250): presses must last longer than that.
#pragma once

#include <filesystem>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "hil_common.h"

namespace hil {

// A vendor-defined descriptor with the CP2112's report IDs (the driver only needs it to parse).
inline const std::vector<uint8_t> kCp2112Descriptor = {
    0x06, 0x00, 0xFF, 0x09, 0x01, 0xA1, 0x01, 0x15, 0x00, 0x26, 0xFF, 0x00, 0x75, 0x08,
    0x85, 0x02, 0x95, 0x04, 0x09, 0x02, 0xB1, 0x02,  // GPIO configuration
    0x85, 0x03, 0x95, 0x01, 0x09, 0x03, 0xB1, 0x02,  // GPIO get
    0x85, 0x04, 0x95, 0x02, 0x09, 0x04, 0xB1, 0x02,  // GPIO set
    0x85, 0x05, 0x95, 0x02, 0x09, 0x05, 0xB1, 0x02,  // version
    0x85, 0x06, 0x95, 0x0D, 0x09, 0x06, 0xB1, 0x02,  // SMBus configuration
    0x85, 0x10, 0x95, 0x3F, 0x09, 0x10, 0x91, 0x02,  // data read request (output)
    0x85, 0x13, 0x95, 0x3F, 0x09, 0x13, 0x81, 0x02,  // data read response (input)
    0x85, 0x16, 0x95, 0x06, 0x09, 0x16, 0x81, 0x02,  // transfer status response (input)
    0x85, 0x20, 0x95, 0x01, 0x09, 0x20, 0xB1, 0x02,  // lock byte
    0xC0};

// The emulated chip: eight pins, pulled up (a button pulls its pin to ground).
class Cp2112 {
 public:
  bool create() {
    dev_.onGetReport([this](uint8_t rnum, uint8_t) -> std::optional<std::vector<uint8_t>> {
      std::lock_guard<std::mutex> lock(m_);
      switch (rnum) {
        case 0x02: return std::vector<uint8_t>{0x02, direction_, pushPull_, 0x00, 0x00};
        case 0x03: ++levelReads_; return std::vector<uint8_t>{0x03, levels_};
        case 0x05: return std::vector<uint8_t>{0x05, 0x0C, 0x02};  // part number, version
        case 0x06: return std::vector<uint8_t>{0x06, 0x00, 0x01, 0x86, 0xA0, 0x02, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00};
        case 0x20: return std::vector<uint8_t>{0x20, 0xFF};
        default: return std::nullopt;
      }
    });
    dev_.onSetReport([this](uint8_t rnum, uint8_t, const std::vector<uint8_t>& d) {
      std::lock_guard<std::mutex> lock(m_);
      if (rnum == 0x02 && d.size() >= 3) direction_ = d[1], pushPull_ = d[2];
      if (rnum == 0x04 && d.size() >= 3) outputs_ = static_cast<uint8_t>((outputs_ & ~d[2]) | (d[1] & d[2]));
      return true;
    });
    return dev_.create("CP2112 HID USB-to-SMBus Bridge", BUS_USB, 0x10c4, 0xea90, kCp2112Descriptor, "emboss-hil-cp2112");
  }
  void destroy() { dev_.destroy(); }
  // Pressed pulls the pin low.
  void press(unsigned pin, bool down) {
    std::lock_guard<std::mutex> lock(m_);
    if (down) levels_ = static_cast<uint8_t>(levels_ & ~(1u << pin));
    else levels_ = static_cast<uint8_t>(levels_ | (1u << pin));
  }
  int levelReads() {
    std::lock_guard<std::mutex> lock(m_);
    return levelReads_;
  }
  const std::string& error() const { return dev_.error(); }

 private:
  Uhid dev_;
  std::mutex m_;
  uint8_t levels_ = 0xFF;
  uint8_t direction_ = 0x00;  // all inputs
  uint8_t pushPull_ = 0x00;
  uint8_t outputs_ = 0x00;
  int levelReads_ = 0;
};

// The gpiochip the driver registered for the emulated chip, as "gpiochipN".
inline std::string findCp2112Chip() {
  std::error_code ec;
  for (const auto& e : std::filesystem::directory_iterator("/sys/bus/gpio/devices", ec)) {
    const auto label = readFile(e.path() / "label");  // not on every kernel: fall back to the parent
    const auto real = std::filesystem::canonical(e.path(), ec).string();
    if (real.find("10C4:EA90") != std::string::npos || (label && trim(*label) == "cp2112_gpio")) return e.path().filename().string();
  }
  return "";
}

// Creates the emulated chip and waits for the driver's gpiochip; both are checks. Returns its name
// ("gpiochipN"), or "" when either failed.
inline std::string startCp2112(Cp2112& chip) {
  if (!check(chip.create(), "uhid CP2112 created %s", chip.error().c_str())) return "";
  std::string name;
  waitFor([&] { return !(name = findCp2112Chip()).empty(); }, 5.0, 0.05);
  check(!name.empty(), "hid-cp2112 registered a gpiochip for it (%s)", name.empty() ? "none: is hid-cp2112 loaded?" : name.c_str());
  return name;
}

}  // namespace hil
