// UC-Logic tablets over libusb: finding them and the string-descriptor handshake (full-resolution mode, true maxima).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "input/hid_decode.h"
#include "util/result.h"

namespace emboss {

struct UclogicUsbDevice {
  uint16_t vendorId = 0;
  uint16_t productId = 0;
  uint8_t bus = 0;
  uint8_t address = 0;
  std::string describe() const;  // "256c:006d on bus 1 address 7"
};

// The connected USB devices of the UC-Logic vendors (0x256c, 0x28bd, 0x5543).
Result<std::vector<UclogicUsbDevice>> enumerateUclogicUsb();

// Reads string descriptor 200 (v2, 18 bytes) and, failing that, 100 (v1, 12 bytes) from the device
// at bus/address. Reading it is what switches the tablet to full-resolution reports. Fails with a
// message naming the device and the cause (permissions, not found, not a UC-Logic protocol).
Result<UclogicPenParams> uclogicHandshake(const UclogicUsbDevice& device);

// The same for the first connected device with this vendor and product ID.
Result<UclogicPenParams> uclogicHandshake(uint16_t vendorId, uint16_t productId);

}  // namespace emboss
