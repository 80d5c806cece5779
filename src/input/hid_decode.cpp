// HID input reports to PenSamples: via a descriptor's pen layout or the Wacom/UC-Logic vendor protocols.
#include "input/hid_decode.h"

#include <algorithm>
#include <cstdio>

namespace emboss {

namespace {

double norm(int64_t v, int64_t lo, int64_t hi) {
  if (hi <= lo) return 0.0;
  return std::clamp((static_cast<double>(v) - static_cast<double>(lo)) / (static_cast<double>(hi) - static_cast<double>(lo)),
                    0.0, 1.0);
}

uint32_t le16(std::span<const uint8_t> d, size_t i) { return d[i] | (uint32_t{d[i + 1]} << 8); }
uint32_t be16(std::span<const uint8_t> d, size_t i) { return (uint32_t{d[i]} << 8) | d[i + 1]; }
uint32_t le24(std::span<const uint8_t> d, size_t i) { return le16(d, i) | (uint32_t{d[i + 2]} << 16); }

std::string hex4(uint16_t v) {
  char b[8];
  std::snprintf(b, sizeof b, "%04x", v);
  return b;
}

// From the kernel's wacom_wac.c feature tables (name, x max, y max, pressure max).
constexpr WacomModel kWacomModels[] = {
    {0x00, "Wacom Penpartner", WacomProtocol::kPenPartner, 5040, 3780, 255},
    {0x10, "Wacom Graphire", WacomProtocol::kGraphire, 10206, 7422, 511},
    {0x11, "Wacom Graphire2 4x5", WacomProtocol::kGraphire, 10206, 7422, 511},
    {0x12, "Wacom Graphire2 5x7", WacomProtocol::kGraphire, 13918, 10206, 511},
    {0x13, "Wacom Graphire3", WacomProtocol::kGraphire, 10208, 7424, 511},
    {0x14, "Wacom Graphire3 6x8", WacomProtocol::kGraphire, 16704, 12064, 511},
    {0x15, "Wacom Graphire4 4x5", WacomProtocol::kGraphire, 10208, 7424, 511},
    {0x16, "Wacom Graphire4 6x8", WacomProtocol::kGraphire, 16704, 12064, 511},
    {0x19, "Wacom Bamboo1 Medium", WacomProtocol::kGraphire, 16704, 12064, 511},
    {0x60, "Wacom Volito", WacomProtocol::kGraphire, 5104, 3712, 511},
    {0x61, "Wacom PenStation2", WacomProtocol::kGraphire, 3250, 2320, 255},
    {0x62, "Wacom Volito2 4x5", WacomProtocol::kGraphire, 5104, 3712, 511},
    {0x63, "Wacom Volito2 2x3", WacomProtocol::kGraphire, 3248, 2320, 511},
    {0x64, "Wacom PenPartner2", WacomProtocol::kGraphire, 3250, 2320, 511},
    {0x69, "Wacom Bamboo1", WacomProtocol::kGraphire, 5104, 3712, 511},
    {0x6a, "Wacom Bamboo1 4x6", WacomProtocol::kGraphire, 14760, 9225, 1023},
    {0x6b, "Wacom Bamboo1 5x8", WacomProtocol::kGraphire, 21648, 13530, 1023},
    {0x20, "Wacom Intuos 4x5", WacomProtocol::kIntuos, 12700, 10600, 1023},
    {0x21, "Wacom Intuos 6x8", WacomProtocol::kIntuos, 20320, 16240, 1023},
    {0x22, "Wacom Intuos 9x12", WacomProtocol::kIntuos, 30480, 24060, 1023},
    {0x23, "Wacom Intuos 12x12", WacomProtocol::kIntuos, 30480, 31680, 1023},
    {0x24, "Wacom Intuos 12x18", WacomProtocol::kIntuos, 45720, 31680, 1023},
    {0x41, "Wacom Intuos2 4x5", WacomProtocol::kIntuos, 12700, 10600, 1023},
    {0x42, "Wacom Intuos2 6x8", WacomProtocol::kIntuos, 20320, 16240, 1023},
    {0x43, "Wacom Intuos2 9x12", WacomProtocol::kIntuos, 30480, 24060, 1023},
    {0x44, "Wacom Intuos2 12x12", WacomProtocol::kIntuos, 30480, 31680, 1023},
    {0x45, "Wacom Intuos2 12x18", WacomProtocol::kIntuos, 45720, 31680, 1023},
    {0xb0, "Wacom Intuos3 4x5", WacomProtocol::kIntuos3, 25400, 20320, 1023},
    {0xb1, "Wacom Intuos3 6x8", WacomProtocol::kIntuos3, 40640, 30480, 1023},
    {0xb2, "Wacom Intuos3 9x12", WacomProtocol::kIntuos3, 60960, 45720, 1023},
    {0xb3, "Wacom Intuos3 12x12", WacomProtocol::kIntuos3, 60960, 60960, 1023},
    {0xb4, "Wacom Intuos3 12x19", WacomProtocol::kIntuos3, 97536, 60960, 1023},
    {0xb5, "Wacom Intuos3 6x11", WacomProtocol::kIntuos3, 54204, 31750, 1023},
    {0xb7, "Wacom Intuos3 4x6", WacomProtocol::kIntuos3, 31496, 19685, 1023},
    {0xb8, "Wacom Intuos4 4x6", WacomProtocol::kIntuos4, 31496, 19685, 2047},
    {0xb9, "Wacom Intuos4 6x9", WacomProtocol::kIntuos4, 44704, 27940, 2047},
    {0xba, "Wacom Intuos4 8x13", WacomProtocol::kIntuos4, 65024, 40640, 2047},
    {0xbb, "Wacom Intuos4 12x19", WacomProtocol::kIntuos4, 97536, 60960, 2047},
};

const char* protocolName(WacomProtocol p) {
  switch (p) {
    case WacomProtocol::kPenPartner: return "penpartner";
    case WacomProtocol::kGraphire: return "graphire";
    case WacomProtocol::kIntuos: return "intuos";
    case WacomProtocol::kIntuos3: return "intuos3";
    case WacomProtocol::kIntuos4: return "intuos4";
  }
  return "?";
}

constexpr uint8_t kWacomReportPen = 2;  // WACOM_REPORT_PENABLED

}  // namespace

// ---------------------------------------------------------------- descriptor layouts

std::optional<PenSample> decodePenReport(const PenLayout& l, bool usesReportIds, std::span<const uint8_t> report,
                                         double time_s) {
  std::span<const uint8_t> data = report;
  if (usesReportIds) {
    if (report.empty() || report[0] != l.reportId) return std::nullopt;
    data = report.subspan(1);
  }
  if (!l.x || !l.y) return std::nullopt;
  const auto x = hidExtractValue(data, *l.x);
  const auto y = hidExtractValue(data, *l.y);
  if (!x || !y) return std::nullopt;
  auto flag = [&](const std::optional<HidValueLoc>& loc) -> std::optional<bool> {
    if (!loc) return std::nullopt;
    const auto v = hidExtractValue(data, *loc);
    if (!v) return std::nullopt;
    return *v != 0;
  };
  PenSample s;
  s.time_s = time_s;
  s.x = norm(*x, l.x->min, l.x->max);
  s.y = norm(*y, l.y->min, l.y->max);
  std::optional<int64_t> p;
  if (l.pressure) p = hidExtractValue(data, *l.pressure);
  const auto tip = flag(l.tip);
  const auto eraser = flag(l.eraser);
  if (tip) {
    s.tip = *tip;
  } else {
    s.tip = p && *p > l.pressure->min;
  }
  if (eraser && *eraser) s.tip = true;
  s.pressure = p ? norm(*p, l.pressure->min, l.pressure->max) : (s.tip ? 1.0 : 0.0);
  const auto inRange = flag(l.inRange);
  s.inRange = (inRange ? *inRange : true) || s.tip;
  s.barrel1 = flag(l.barrel1).value_or(false);
  s.barrel2 = flag(l.barrel2).value_or(false);
  return s;
}

DescriptorPenDecoder::DescriptorPenDecoder(std::vector<PenLayout> pens, bool usesReportIds)
    : pens_(std::move(pens)), usesReportIds_(usesReportIds) {}

std::string DescriptorPenDecoder::name() const {
  std::string s = "descriptor";
  for (const auto& p : pens_) s += " report " + std::to_string(p.reportId);
  return s;
}

std::optional<PenSample> DescriptorPenDecoder::decode(std::span<const uint8_t> report, double time_s) {
  for (const auto& p : pens_) {
    if (auto s = decodePenReport(p, usesReportIds_, report, time_s)) {
      last_ = s;
      lastHasInRange_ = p.inRange.has_value();
      return s;
    }
  }
  return std::nullopt;
}

std::optional<PenSample> DescriptorPenDecoder::idle(double now_s) {
  if (lastHasInRange_ || !last_ || !last_->inRange || now_s - last_->time_s < 0.1) return std::nullopt;
  PenSample s = *last_;
  s.time_s = now_s;
  s.pressure = 0.0;
  s.tip = s.inRange = s.barrel1 = s.barrel2 = false;
  last_ = s;
  return s;
}

// ---------------------------------------------------------------- Wacom

const WacomModel* findWacomModel(uint16_t vendorId, uint16_t productId) {
  if (vendorId != kWacomVendorId) return nullptr;
  for (const auto& m : kWacomModels) {
    if (m.productId == productId) return &m;
  }
  return nullptr;
}

WacomPenDecoder::WacomPenDecoder(const WacomModel& model) : model_(model) {}

std::string WacomPenDecoder::name() const { return std::string("wacom ") + protocolName(model_.protocol) + ": " + model_.name; }

PenSample WacomPenDecoder::make(double t, int32_t x, int32_t y, int32_t pressure, bool tip, bool inRange, bool b1,
                                bool b2) const {
  PenSample s;
  s.time_s = t;
  s.x = norm(x, 0, model_.xMax);
  s.y = norm(y, 0, model_.yMax);
  s.pressure = norm(pressure, 0, model_.pressureMax);
  s.tip = tip;
  s.inRange = inRange || tip;
  s.barrel1 = b1;
  s.barrel2 = b2;
  return s;
}

PenSample WacomPenDecoder::outOfRange(double t) const {
  PenSample s = last_;
  s.time_s = t;
  s.pressure = 0.0;
  s.tip = s.inRange = s.barrel1 = s.barrel2 = false;
  return s;
}

std::optional<PenSample> WacomPenDecoder::decode(std::span<const uint8_t> report, double time_s) {
  std::optional<PenSample> s;
  switch (model_.protocol) {
    case WacomProtocol::kPenPartner: s = penPartner(report, time_s); break;
    case WacomProtocol::kGraphire: s = graphire(report, time_s); break;
    default: s = intuos(report, time_s); break;
  }
  if (s) last_ = *s;
  return s;
}

// wacom_penpartner_irq: report 1 with a proximity bit, report 2 always in proximity; pressure is a
// signed byte offset by 127.
std::optional<PenSample> WacomPenDecoder::penPartner(std::span<const uint8_t> d, double t) {
  if (d.size() < 7) return std::nullopt;
  const int32_t pressure = std::max(0, static_cast<int8_t>(d[6]) + 127);
  if (d[0] == 1) {
    if (!(d[5] & 0x80)) {
      if (!inProx_) return std::nullopt;
      inProx_ = false;
      return outOfRange(t);
    }
    inProx_ = true;
    return make(t, static_cast<int32_t>(le16(d, 1)), static_cast<int32_t>(le16(d, 3)), pressure,
                static_cast<int8_t>(d[6]) > -127, true, d[5] & 0x40, false);
  }
  if (d[0] == 2) {
    inProx_ = true;
    return make(t, static_cast<int32_t>(le16(d, 1)), static_cast<int32_t>(le16(d, 3)), pressure,
                static_cast<int8_t>(d[6]) > -80 && !(d[5] & 0x20), true, d[5] & 0x40, false);
  }
  return std::nullopt;
}

// wacom_graphire_irq: report 2; byte 1 = proximity 0x80, tool (bits 5-6: 0 pen, 1 eraser, 2-3
// mouse), buttons 0x04/0x02, tip 0x01; x, y little-endian 16 bits; pressure byte 6 plus 2 bits of byte 7.
std::optional<PenSample> WacomPenDecoder::graphire(std::span<const uint8_t> d, double t) {
  if (d.size() < 8 || d[0] != kWacomReportPen) return std::nullopt;
  const bool prox = d[1] & 0x80;
  if (!prox) {
    if (!inProx_) return std::nullopt;
    inProx_ = false;
    return penTool_ ? std::optional<PenSample>(outOfRange(t)) : std::nullopt;
  }
  inProx_ = true;
  const unsigned tool = (d[1] >> 5) & 3u;
  penTool_ = tool <= 1;
  if (!penTool_) return std::nullopt;  // the mouse
  const int32_t pressure = std::min<int32_t>(static_cast<int32_t>(d[6] | ((d[7] & 0x03u) << 8)), model_.pressureMax);
  return make(t, static_cast<int32_t>(le16(d, 2)), static_cast<int32_t>(le16(d, 4)), pressure, d[1] & 0x01, true,
              d[1] & 0x02, d[1] & 0x04);
}

// wacom_intuos_irq: report 2 (5, 6 for the second tool); an enter-proximity packet names the tool,
// an exit packet ends it, general pen packets carry pressure and buttons.
std::optional<PenSample> WacomPenDecoder::intuos(std::span<const uint8_t> d, double t) {
  if (d.size() < 10) return std::nullopt;
  if (d[0] != kWacomReportPen && d[0] != 5 && d[0] != 6) return std::nullopt;
  if ((d[1] & 0xfc) == 0xc0) {  // enter proximity: tool id
    const uint32_t id = (uint32_t{d[2]} << 4) | (d[3] >> 4) | ((uint32_t{d[7]} & 0x0f) << 20) | ((uint32_t{d[8]} & 0xf0) << 12);
    switch (id & 0xfffff) {
      case 0x007: case 0x09c: case 0x094: case 0x017: case 0x806:  // mice
      case 0x096: case 0x097: case 0x006:                          // lens cursors
        penTool_ = false;
        break;
      default:
        penTool_ = true;
        break;
    }
    inProx_ = true;
    return std::nullopt;
  }
  if ((d[1] & 0xfe) == 0x80) {  // exit proximity
    const bool was = inProx_ && penTool_;
    inProx_ = false;
    return was ? std::optional<PenSample>(outOfRange(t)) : std::nullopt;
  }
  const bool general = (d[1] & 0xb8) == 0xa0;
  if (!inProx_) {
    if (!general) return std::nullopt;
    inProx_ = true;  // started while the pen was already near: assume a pen
    penTool_ = true;
  }
  if (!penTool_) return std::nullopt;
  int32_t x = 0;
  int32_t y = 0;
  if (model_.protocol == WacomProtocol::kIntuos) {
    x = static_cast<int32_t>(be16(d, 2));
    y = static_cast<int32_t>(be16(d, 4));
  } else {
    x = static_cast<int32_t>((uint32_t{d[2]} << 9) | (uint32_t{d[3]} << 1) | ((d[9] >> 1) & 1u));
    y = static_cast<int32_t>((uint32_t{d[4]} << 9) | (uint32_t{d[5]} << 1) | (d[9] & 1u));
  }
  if (!general) {  // other packets (airbrush wheel, rotation): position only
    PenSample s = last_;
    s.time_s = t;
    s.x = norm(x, 0, model_.xMax);
    s.y = norm(y, 0, model_.yMax);
    s.inRange = true;
    return s;
  }
  uint32_t p = (uint32_t{d[6]} << 2) | ((d[7] >> 6) & 3u);
  if (model_.protocol == WacomProtocol::kIntuos4) p = (p << 1) | (d[1] & 1u);
  return make(t, x, y, static_cast<int32_t>(p), p > 10, true, d[1] & 0x02, d[1] & 0x04);
}

// ---------------------------------------------------------------- UC-Logic

bool isUclogicVendor(uint16_t vendorId) { return vendorId == 0x256c || vendorId == 0x28bd || vendorId == 0x5543; }

Result<UclogicPenParams> parseUclogicPenString(uint8_t index, std::span<const uint8_t> d) {
  UclogicPenParams p;
  size_t need = 0;
  if (index == kUclogicV1StringIndex) {
    p.version = 1;
    need = 12;
  } else if (index == kUclogicV2StringIndex) {
    p.version = 2;
    need = 18;
  } else {
    return fail("string descriptor " + std::to_string(index) + " is not a UC-Logic pen-parameter index (100 or 200)");
  }
  if (d.size() < need) {
    return fail("string descriptor " + std::to_string(index) + " has " + std::to_string(d.size()) + " bytes, expected " +
                std::to_string(need) + ": the tablet does not speak this UC-Logic protocol version");
  }
  if (d[1] != 0x03) return fail("string descriptor " + std::to_string(index) + " is not a USB string descriptor (type byte is not 3)");
  if (p.version == 2) {
    // Some tablets answer every unknown index with the model name in UTF-16LE: not parameters.
    bool text = true;
    for (size_t i = 2; i + 1 < need && text; i += 2) text = d[i] >= 0x20 && d[i] < 0x7f && d[i + 1] == 0;
    if (text) return fail("string descriptor 200 holds only text, not pen parameters: not a UC-Logic v2 tablet");
    p.xMax = static_cast<int32_t>(le24(d, 2));
    p.yMax = static_cast<int32_t>(le24(d, 5));
  } else {
    p.xMax = static_cast<int32_t>(le16(d, 2));
    p.yMax = static_cast<int32_t>(le16(d, 4));
  }
  p.pressureMax = static_cast<int32_t>(le16(d, 8));
  p.resolution = static_cast<uint16_t>(le16(d, 10));
  if (p.xMax <= 0 || p.yMax <= 0 || p.pressureMax <= 0) {
    return fail("string descriptor " + std::to_string(index) + " gives a zero maximum (x " + std::to_string(p.xMax) +
                ", y " + std::to_string(p.yMax) + ", pressure " + std::to_string(p.pressureMax) + ")");
  }
  return p;
}

UclogicPenDecoder::UclogicPenDecoder(const UclogicPenParams& params) : params_(params) {}

std::string UclogicPenDecoder::name() const {
  return "uc-logic v" + std::to_string(params_.version) + " (" + std::to_string(params_.xMax) + "x" +
         std::to_string(params_.yMax) + ", pressure " + std::to_string(params_.pressureMax) + ")";
}

std::optional<PenSample> UclogicPenDecoder::decode(std::span<const uint8_t> d, double t) {
  const size_t need = params_.version == 1 ? 8 : 10;
  if (d.size() < need || d[0] != params_.reportId()) return std::nullopt;
  const uint8_t status = d[1];
  if ((status & 0xf0) == 0xe0 || (status & 0xf0) == 0xf0) return std::nullopt;  // frame buttons, dials, battery
  if (params_.version == 1 && (status & 0x20)) return std::nullopt;             // v1 frame sub-report
  PenSample s;
  s.time_s = t;
  uint32_t x = 0;
  uint32_t y = 0;
  uint32_t p = le16(d, 6);
  if (params_.version == 2) {  // fragmented high resolution: x, y high bytes after the pressure
    x = le16(d, 2) | (uint32_t{d[8]} << 16);
    y = le16(d, 4) | (uint32_t{d[9]} << 16);
    s.inRange = true;  // v2 never reports leaving; idle() does
  } else {
    x = le16(d, 2);
    y = le16(d, 4);
    s.inRange = !(status & 0x40);  // inverted in-range bit
  }
  s.x = norm(x, 0, params_.xMax);
  s.y = norm(y, 0, params_.yMax);
  s.pressure = norm(p, 0, params_.pressureMax);
  s.tip = status & 0x01;
  s.inRange = s.inRange || s.tip;
  s.barrel1 = status & 0x02;
  s.barrel2 = status & 0x04;
  last_ = s;
  inRange_ = s.inRange;
  return s;
}

std::optional<PenSample> UclogicPenDecoder::idle(double now_s) {
  if (params_.version != 2 || !inRange_ || now_s - last_.time_s < 0.1) return std::nullopt;
  inRange_ = false;
  PenSample s = last_;
  s.time_s = now_s;
  s.pressure = 0.0;
  s.tip = s.inRange = s.barrel1 = s.barrel2 = false;
  return s;
}

// ---------------------------------------------------------------- chains and the choice

ChainPenDecoder::ChainPenDecoder(std::vector<std::unique_ptr<PenReportDecoder>> decoders) : decoders_(std::move(decoders)) {}

std::string ChainPenDecoder::name() const {
  std::string s;
  for (const auto& d : decoders_) s += (s.empty() ? "" : ", then ") + d->name();
  return s;
}

std::optional<PenSample> ChainPenDecoder::decode(std::span<const uint8_t> report, double time_s) {
  for (auto& d : decoders_) {
    if (auto s = d->decode(report, time_s)) return s;
  }
  return std::nullopt;
}

std::optional<PenSample> ChainPenDecoder::idle(double now_s) {
  for (auto& d : decoders_) {
    if (auto s = d->idle(now_s)) return s;
  }
  return std::nullopt;
}

Result<std::unique_ptr<PenReportDecoder>> makePenDecoder(uint16_t vendorId, uint16_t productId,
                                                         std::span<const uint8_t> descriptor,
                                                         const std::optional<UclogicPenParams>& uclogic) {
  if (const WacomModel* m = findWacomModel(vendorId, productId)) {
    return std::unique_ptr<PenReportDecoder>(std::make_unique<WacomPenDecoder>(*m));
  }
  std::vector<PenLayout> pens;
  bool usesIds = false;
  std::string descriptorProblem;
  auto parsed = parseHidDescriptor(descriptor);
  if (parsed) {
    pens = findPens(*parsed);
    usesIds = parsed->usesReportIds;
    if (pens.empty()) descriptorProblem = "its report descriptor describes no pen (digitizer stylus with X and Y)";
  } else {
    descriptorProblem = parsed.error();
  }
  const std::string id = hex4(vendorId) + ":" + hex4(productId);
  if (isUclogicVendor(vendorId) && uclogic) {
    const uint8_t rid = uclogic->reportId();
    const bool described = std::any_of(pens.begin(), pens.end(), [&](const PenLayout& l) { return l.reportId == rid; });
    if (!described) {
      std::vector<std::unique_ptr<PenReportDecoder>> chain;
      chain.push_back(std::make_unique<UclogicPenDecoder>(*uclogic));
      if (!pens.empty()) chain.push_back(std::make_unique<DescriptorPenDecoder>(pens, usesIds));
      if (chain.size() == 1) return std::move(chain.front());
      return std::unique_ptr<PenReportDecoder>(std::make_unique<ChainPenDecoder>(std::move(chain)));
    }
  }
  if (!pens.empty()) return std::unique_ptr<PenReportDecoder>(std::make_unique<DescriptorPenDecoder>(std::move(pens), usesIds));
  std::string hint;
  if (isUclogicVendor(vendorId)) {
    hint = "; a UC-Logic tablet needs its string-descriptor handshake first (hid-uclogic in the kernel, or emboss's libusb handshake)";
  } else if (vendorId == kWacomVendorId) {
    hint = "; not a known fixed-packet Wacom model either (the kernel's wacom driver and evdev handle it)";
  }
  return fail("device " + id + ": " + descriptorProblem + hint);
}

}  // namespace emboss
