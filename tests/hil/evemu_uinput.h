// An evemu recording's device as a uinput device description (name, IDs, keys, axes, properties).
#pragma once

#include <linux/input.h>

#include <sstream>

#include "hil_common.h"
#include "input/evemu.h"

namespace hil {

// The INPUT_PROP_* bits of the P: lines (the project's evemu parser skips them).
inline std::vector<int> parseProps(const std::filesystem::path& file) {
  std::vector<int> props;
  auto text = readFile(file);
  if (!text) return props;
  std::istringstream in(*text);
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("P:", 0) != 0) continue;
    std::istringstream words(line.substr(2));
    std::string w;
    for (int byte = 0; words >> w; ++byte) {
      const unsigned v = static_cast<unsigned>(std::stoul(w, nullptr, 16));
      for (int bit = 0; bit < 8; ++bit)
        if (v & (1u << bit)) props.push_back(byte * 8 + bit);
    }
  }
  return props;
}

// Axes get fuzz 0: a recording holds values the kernel already filtered once.
inline Uinput::Spec specFor(const emboss::EvemuDevice& d, const std::vector<int>& props) {
  Uinput::Spec s;
  s.name = d.name;
  s.bus = d.bus ? d.bus : BUS_USB;
  s.vendor = d.vendor;
  s.product = d.product;
  s.version = d.version;
  for (const auto& [type, bytes] : d.bits) {
    if (type == EV_SYN || type == EV_ABS) continue;
    for (size_t i = 0; i < bytes.size(); ++i)
      for (int bit = 0; bit < 8; ++bit)
        if (bytes[i] & (1u << bit)) s.codes.emplace_back(type, static_cast<int>(i * 8 + bit));
  }
  for (const auto& [code, r] : d.axes) s.axes.push_back({code, r.min, r.max, 0, r.flat, r.resolution});
  s.props = props;
  return s;
}

}  // namespace hil
