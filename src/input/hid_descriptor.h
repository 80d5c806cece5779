// HID report descriptors: a parser producing the report fields, and a finder for the pen in them.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "util/result.h"

namespace emboss {

// Usages are 32 bits: usage page << 16 | usage id.
inline constexpr uint32_t hidUsage(uint16_t page, uint16_t id) { return (uint32_t{page} << 16) | id; }

namespace hidusage {
inline constexpr uint32_t kX = hidUsage(0x01, 0x30);
inline constexpr uint32_t kY = hidUsage(0x01, 0x31);
inline constexpr uint32_t kDigitizer = hidUsage(0x0d, 0x01);
inline constexpr uint32_t kPen = hidUsage(0x0d, 0x02);
inline constexpr uint32_t kStylus = hidUsage(0x0d, 0x20);
inline constexpr uint32_t kPuck = hidUsage(0x0d, 0x21);
inline constexpr uint32_t kFinger = hidUsage(0x0d, 0x22);
inline constexpr uint32_t kTipPressure = hidUsage(0x0d, 0x30);
inline constexpr uint32_t kInRange = hidUsage(0x0d, 0x32);
inline constexpr uint32_t kInvert = hidUsage(0x0d, 0x3c);
inline constexpr uint32_t kTipSwitch = hidUsage(0x0d, 0x42);
inline constexpr uint32_t kBarrelSwitch = hidUsage(0x0d, 0x44);
inline constexpr uint32_t kEraser = hidUsage(0x0d, 0x45);
inline constexpr uint32_t kSecondaryBarrelSwitch = hidUsage(0x0d, 0x5a);
}  // namespace hidusage

// Wacom's vendor digitizer page 0xFF0D mirrors the standard pages (as the kernel's
// wacom_equivalent_usage does): 0xFF0D00xx is digitizer 0x0D/xx, 0xFF0D01xx generic desktop 0x01/xx.
uint32_t hidEquivalentUsage(uint32_t usage);

enum class HidReportType : uint8_t { kInput, kOutput, kFeature };

// A run of usages from one Usage item (min == max) or a Usage Minimum/Maximum pair.
struct HidUsageRange {
  uint32_t min = 0;
  uint32_t max = 0;
};

struct HidCollection {
  uint32_t usage = 0;
  uint8_t type = 0;  // 0 physical, 1 application, 2 logical, ...
  int parent = -1;   // index into HidDescriptor::collections, -1 at top level
};

// One Input, Output or Feature main item: count values of size bits each.
struct HidField {
  HidReportType type = HidReportType::kInput;
  uint8_t reportId = 0;      // 0 when the descriptor declares no report IDs
  uint32_t bitOffset = 0;    // of the first value, counted after the report-ID byte
  uint32_t size = 0;         // bits per value
  uint32_t count = 0;
  uint32_t flags = 0;        // main item data: bit 0 constant, bit 1 variable, bit 2 relative, bit 6 null state
  int32_t logicalMin = 0;
  int32_t logicalMax = 0;
  int32_t physicalMin = 0;
  int32_t physicalMax = 0;
  int32_t unitExponent = 0;
  uint32_t unit = 0;
  std::vector<HidUsageRange> usages;  // in declaration order
  int collection = -1;                // innermost enclosing collection, -1 at top level

  bool isConstant() const { return flags & 1u; }
  bool isVariable() const { return flags & 2u; }
  bool isRelative() const { return flags & 4u; }
  // The usage of value i (variable fields): the i-th declared usage, the last one repeating.
  uint32_t usageAt(uint32_t i) const;
};

struct HidDescriptor {
  std::vector<HidField> fields;
  std::vector<HidCollection> collections;
  bool usesReportIds = false;
  std::vector<std::string> warnings;  // oddities the parser tolerated
  // Length in bits of a report's data (after the report-ID byte).
  uint32_t reportBits(HidReportType type, uint8_t reportId) const;
};

// Parses a report descriptor: short items (main, global, local), long items (skipped), Push/Pop,
// report IDs, 16-bit usages completed with the usage page and extended 32-bit usages, usage
// minimum/maximum, collections. Fails with a message naming the byte offset on malformed input, and
// with a plain explanation for an empty descriptor.
Result<HidDescriptor> parseHidDescriptor(std::span<const uint8_t> bytes);

// Where a value sits in a report.
struct HidValueLoc {
  uint32_t bit = 0;   // offset after the report-ID byte
  uint32_t size = 0;  // bits
  int32_t min = 0;    // logical
  int32_t max = 0;
};

// A pen (stylus) found in a descriptor: the input report carrying it and where its values are.
struct PenLayout {
  uint8_t reportId = 0;
  uint32_t reportBits = 0;  // data length after the report-ID byte
  uint32_t application = 0;
  std::optional<HidValueLoc> x, y, pressure, tip, inRange, barrel1, barrel2, eraser, invert;
  std::string describe() const;  // one line for logs and `emboss-input list`
};

// The pens in a descriptor: input values inside a Stylus collection or a Pen (or Digitizer)
// application, not inside a Finger or Puck collection, with X and Y. One layout per report ID and
// pen collection; the first value of each usage wins.
std::vector<PenLayout> findPens(const HidDescriptor& descriptor);

// Reads size bits (size <= 32) at bit offset from little-endian report data; nullopt past the end.
std::optional<uint32_t> hidExtractBits(std::span<const uint8_t> data, uint32_t bit, uint32_t size);
// The same, sign-extended when the logical minimum is negative.
std::optional<int64_t> hidExtractValue(std::span<const uint8_t> data, const HidValueLoc& loc);

}  // namespace emboss
