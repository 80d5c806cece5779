// hid-recorder captures (R: descriptor, N:, P:, I: bus vid pid, E: time len bytes) parsed and decoded.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "devices/pen.h"
#include "util/result.h"

namespace emboss {

struct HidRecordReport {
  double time_s = 0.0;
  std::vector<uint8_t> bytes;  // the report-ID byte first when the device numbers its reports
};

struct HidRecording {
  std::string name;
  std::string phys;
  uint16_t bus = 0;
  uint16_t vendorId = 0;
  uint16_t productId = 0;
  std::vector<uint8_t> descriptor;
  std::vector<HidRecordReport> reports;
};

// Parses a capture. Only the first device ("D: 0", or the only one) is kept when a capture holds
// several; repeated R:/N:/P:/I: lines for it (hid-recorder repeats them) are checked for agreement.
// Malformed lines fail with their line number.
Result<HidRecording> parseHidRecord(std::string_view text);
Result<HidRecording> loadHidRecord(const std::filesystem::path& path);

// Decodes every report with the decoder makePenDecoder picks for the capture's device.
Result<std::vector<PenSample>> decodeHidRecording(const HidRecording& recording);

}  // namespace emboss
