// Finding the tablet: every evdev and hidraw device with the back end it would get, and opening the first usable one.
#include "pen/pen_probe.h"

#include <algorithm>
#include <cstdio>
#include <optional>

#include "input/evdev_pen_state.h"
#include "input/hid_decode.h"
#include "pen/pen_evdev.h"
#include "pen/pen_hidraw.h"
#include "pen/usb_uclogic.h"
#include "platform_util.h"

namespace emboss {

namespace {

std::string rangeText(const EvdevCaps& caps) {
  std::string s;
  auto add = [&](const char* name, int code) {
    const auto it = caps.abs.find(code);
    if (it == caps.abs.end()) return;
    s += (s.empty() ? "" : ", ") + std::string(name) + " " + std::to_string(it->second.min) + ".." +
         std::to_string(it->second.max);
  };
  add("x", evcode::kAbsX);
  add("y", evcode::kAbsY);
  add("pressure", evcode::kAbsPressure);
  return s;
}

// Whether a descriptor already describes the UC-Logic pen report (the kernel's hid-uclogic rewrote it).
bool describesReport(const std::vector<uint8_t>& descriptor, uint8_t reportId) {
  auto d = parseHidDescriptor(descriptor);
  if (!d) return false;
  const auto pens = findPens(*d);
  return std::any_of(pens.begin(), pens.end(), [&](const PenLayout& l) { return l.reportId == reportId; });
}

struct HidrawChoice {
  std::unique_ptr<PenReportDecoder> decoder;
  std::string why;  // when there is no decoder
};

HidrawChoice chooseHidrawDecoder(const HidrawDeviceInfo& info, const std::vector<uint8_t>& descriptor) {
  std::optional<UclogicPenParams> params;
  std::string handshakeProblem;
  if (isUclogicVendor(info.vendorId) && !findWacomModel(info.vendorId, info.productId) &&
      !describesReport(descriptor, 8) && !describesReport(descriptor, 7) && info.interfaceNumber <= 0) {
    auto p = uclogicHandshake(info.vendorId, info.productId);
    if (p) {
      params = *p;
    } else {
      handshakeProblem = p.error();
    }
  }
  auto decoder = makePenDecoder(info.vendorId, info.productId, descriptor, params);
  if (decoder) return {std::move(*decoder), {}};
  return {nullptr, decoder.error() + (handshakeProblem.empty() ? "" : "; " + handshakeProblem)};
}

}  // namespace

std::vector<DeviceReport> probeTablets() {
  std::vector<DeviceReport> out;
  for (const auto& node : listEvdevNodes()) {
    DeviceReport r;
    r.backend = "evdev";
    r.path = node.string();
    auto caps = readEvdevCaps(node);
    if (!caps) {
      r.detail = caps.error();
      out.push_back(std::move(r));
      continue;
    }
    r.name = caps->name;
    r.vendorId = caps->vendorId;
    r.productId = caps->productId;
    if (auto why = evdevUnusableReason(*caps)) {
      r.detail = *why;
    } else {
      r.usable = true;
      r.detail = "evdev back end, grabbed (" + rangeText(*caps) + ")";
    }
    out.push_back(std::move(r));
  }
  auto hid = enumerateHidraw();
  if (!hid) {
    DeviceReport r;
    r.backend = "hidraw";
    r.detail = hid.error();
    out.push_back(std::move(r));
    return out;
  }
  for (const auto& info : *hid) {
    DeviceReport r;
    r.backend = "hidraw";
    r.path = info.path;
    r.name = info.describe();
    r.vendorId = info.vendorId;
    r.productId = info.productId;
    auto descriptor = readHidrawDescriptor(info.path);
    if (!descriptor) {
      r.detail = descriptor.error();
      out.push_back(std::move(r));
      continue;
    }
    auto choice = chooseHidrawDecoder(info, *descriptor);
    if (choice.decoder) {
      r.usable = true;
      r.detail = "hidraw back end, " + choice.decoder->name();
      const bool evdevToo = std::any_of(out.begin(), out.end(), [&](const DeviceReport& e) {
        return e.backend == "evdev" && e.usable && e.vendorId == info.vendorId && e.productId == info.productId;
      });
      if (evdevToo) r.detail += " (its evdev node is preferred)";
    } else {
      r.detail = choice.why;
    }
    out.push_back(std::move(r));
  }
  return out;
}

Result<std::unique_ptr<PenSource>> openFirstTablet() {
  std::vector<std::string> problems;
  for (const auto& node : listEvdevNodes()) {
    auto caps = readEvdevCaps(node);
    if (!caps || evdevUnusableReason(*caps)) continue;  // not a tablet: not worth a log line
    auto pen = EvdevPen::open(node, true);
    if (pen) {
      std::fprintf(stderr, "emboss: using %s (%s)\n", node.c_str(), caps->name.c_str());
      return std::unique_ptr<PenSource>(std::move(*pen));
    }
    logOnce(pen.error());
    problems.push_back(pen.error());
  }
  auto hid = enumerateHidraw();
  if (!hid) {
    logOnce(hid.error());
    problems.push_back(hid.error());
  } else {
    for (const auto& info : *hid) {
      auto descriptor = readHidrawDescriptor(info.path);
      if (!descriptor) {
        logOnce(descriptor.error());
        continue;
      }
      auto choice = chooseHidrawDecoder(info, *descriptor);
      if (!choice.decoder) continue;  // keyboards, mice and the like
      auto pen = HidrawPen::open(info, std::move(choice.decoder));
      if (pen) {
        std::fprintf(stderr, "emboss: using %s as %s\n", info.describe().c_str(), (*pen)->name().c_str());
        return std::unique_ptr<PenSource>(std::move(*pen));
      }
      logOnce(pen.error());
      problems.push_back(pen.error());
    }
  }
  std::string msg = "no tablet found";
  if (!problems.empty()) {
    msg += ": ";
    for (size_t i = 0; i < problems.size(); ++i) msg += (i ? "; " : "") + problems[i];
  } else {
    msg += " (no evdev node or hidraw device looks like a pen tablet; `emboss-input list` tells why)";
  }
  return fail(msg);
}

}  // namespace emboss
