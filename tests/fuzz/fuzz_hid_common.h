// Shared by the HID fuzz targets: feeding descriptors, reports, evemu and hid-recorder texts to the parsers.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string_view>
#include <vector>

#include "input/evemu.h"
#include "input/hid_decode.h"
#include "input/hid_descriptor.h"
#include "input/hidrecord.h"

namespace emboss::fuzz {

using Bytes = std::span<const uint8_t>;

// Normalised values must stay in 0..1 (and not be NaN) whatever the input.
inline bool outside(double v) { return !(v >= 0.0 && v <= 1.0); }
inline bool badSample(const emboss::PenSample& s) { return outside(s.x) || outside(s.y) || outside(s.pressure); }

// Feeds length-prefixed chunks of data to a decoder as reports.
inline void feedReports(emboss::PenReportDecoder& decoder, Bytes data) {
  double t = 0.0;
  size_t i = 0;
  while (i < data.size()) {
    const size_t len = data[i] % 48;
    ++i;
    const size_t n = std::min(len, data.size() - i);
    const auto s = decoder.decode(data.subspan(i, n), t);
    if (s && badSample(*s)) __builtin_trap();
    i += n;
    t += 0.05;
    if ((len & 7) == 0) decoder.idle(t + 0.2);
  }
  (void)decoder.name();
}

inline void fuzzDescriptor(Bytes data) {
  if (data.size() < 6) return;
  const size_t descLen = std::min<size_t>(data[0] | (size_t{data[1]} << 8), data.size() - 6);
  const uint16_t vid = static_cast<uint16_t>(data[2] | (data[3] << 8));
  const uint16_t pid = static_cast<uint16_t>(data[4] | (data[5] << 8));
  const Bytes desc = data.subspan(6, descLen);
  const Bytes reports = data.subspan(6 + descLen);
  if (auto d = emboss::parseHidDescriptor(desc)) {
    for (const auto& f : d->fields) (void)f.usageAt(f.count ? f.count - 1 : 0);
    for (const auto& p : emboss::findPens(*d)) (void)p.describe();
  }
  std::optional<emboss::UclogicPenParams> params;
  if (vid & 1) params = emboss::UclogicPenParams{(pid & 1) ? 1 : 2, 1 + (pid >> 4), 1 + (pid & 0xff), 1 + (vid >> 8), 0};
  if (auto dec = emboss::makePenDecoder(vid, pid, desc, params)) feedReports(**dec, reports);
}

inline void fuzzWacom(Bytes data) {
  if (data.empty()) return;
  static const uint16_t kPids[] = {0x00, 0x61, 0x20, 0xb1, 0xb9};
  const auto* model = emboss::findWacomModel(emboss::kWacomVendorId, kPids[data[0] % 5]);
  if (!model) __builtin_trap();
  emboss::WacomPenDecoder decoder(*model);
  feedReports(decoder, data.subspan(1));
}

inline void fuzzUclogic(Bytes data) {
  if (data.size() < 2) return;
  const uint8_t index = (data[0] & 1) ? emboss::kUclogicV1StringIndex : emboss::kUclogicV2StringIndex;
  const size_t strLen = std::min<size_t>(data[1] % 24, data.size() - 2);
  auto params = emboss::parseUclogicPenString(index, data.subspan(2, strLen));
  if (!params) return;
  emboss::UclogicPenDecoder decoder(*params);
  feedReports(decoder, data.subspan(2 + strLen));
}

inline void fuzzEvemu(Bytes data) {
  const std::string_view text(reinterpret_cast<const char*>(data.data()), data.size());
  auto rec = emboss::parseEvemu(text);
  if (!rec) return;
  for (int code = 0; code < 0x300; code += 7) (void)rec->device.hasKey(code);
  if (auto samples = emboss::evemuToSamples(*rec)) {
    for (const auto& s : *samples) {
      if (badSample(s)) __builtin_trap();
    }
    (void)emboss::splitStrokes(*samples);
  }
}

inline void fuzzHidRecord(Bytes data) {
  const std::string_view text(reinterpret_cast<const char*>(data.data()), data.size());
  auto rec = emboss::parseHidRecord(text);
  if (!rec) return;
  (void)emboss::decodeHidRecording(*rec);
}

}  // namespace emboss::fuzz
