// HID report descriptors: a parser producing the report fields, and a finder for the pen in them.
#include "input/hid_descriptor.h"

#include <algorithm>
#include <cstdio>
#include <iterator>
#include <map>
#include <tuple>

namespace emboss {

namespace {

// Limits as in the Linux HID core: larger values are malformed or hostile descriptors.
constexpr uint32_t kMaxReportSize = 256;      // bits per value
constexpr uint32_t kMaxReportCount = 12288;   // HID_MAX_USAGES
constexpr uint64_t kMaxReportBits = 16384 * 8;  // HID_MAX_BUFFER_SIZE
constexpr size_t kMaxGlobalStack = 32;
constexpr size_t kMaxCollectionDepth = 64;

struct GlobalState {
  uint32_t usagePage = 0;
  int32_t logicalMin = 0;
  int32_t logicalMax = 0;
  int32_t physicalMin = 0;
  int32_t physicalMax = 0;
  int32_t unitExponent = 0;
  uint32_t unit = 0;
  uint32_t reportSize = 0;
  uint32_t reportId = 0;
  uint32_t reportCount = 0;
};

struct LocalUsage {
  HidUsageRange range;
  bool shortForm = false;  // declared with 1 or 2 bytes: completed with the usage page
};

uint32_t complete(uint32_t page, uint32_t id) { return ((page & 0xffffu) << 16) | (id & 0xffffu); }

std::string at(size_t offset) { return " at byte " + std::to_string(offset); }

std::string hex2(uint8_t v) {
  char b[4];
  std::snprintf(b, sizeof b, "%02x", v);
  return b;
}

}  // namespace

uint32_t hidEquivalentUsage(uint32_t usage) {
  if ((usage >> 16) != 0xff0d) return usage;
  const uint32_t subpage = (usage >> 8) & 0xff;
  const uint32_t id = usage & 0xff;
  if (subpage == 0x00) return hidUsage(0x0d, static_cast<uint16_t>(id));
  if (subpage == 0x01) return hidUsage(0x01, static_cast<uint16_t>(id));
  return usage;
}

uint32_t HidField::usageAt(uint32_t i) const {
  if (usages.empty()) return 0;
  uint64_t rest = i;
  for (const auto& r : usages) {
    const uint64_t span = uint64_t{r.max} - r.min + 1;
    if (rest < span) return r.min + static_cast<uint32_t>(rest);
    rest -= span;
  }
  return usages.back().max;
}

uint32_t HidDescriptor::reportBits(HidReportType type, uint8_t reportId) const {
  uint64_t bits = 0;
  for (const auto& f : fields) {
    if (f.type != type || f.reportId != reportId) continue;
    bits = std::max<uint64_t>(bits, uint64_t{f.bitOffset} + uint64_t{f.size} * f.count);
  }
  return static_cast<uint32_t>(bits);
}

Result<HidDescriptor> parseHidDescriptor(std::span<const uint8_t> bytes) {
  if (bytes.empty()) {
    return fail("the report descriptor is empty (0 bytes): the device or capture gave no descriptor; "
                "read it again from /sys/class/hidraw/hidrawN/device/report_descriptor with the tablet plugged in");
  }
  HidDescriptor d;
  GlobalState g;
  std::vector<GlobalState> globalStack;
  std::vector<LocalUsage> locals;
  uint32_t usageMin = 0;
  bool haveUsageMin = false;
  bool usageMinShort = false;
  std::vector<int> open;  // collection stack
  std::map<std::pair<int, uint32_t>, uint64_t> offsets;  // (report type, id) -> bits so far
  bool warnedDelimiter = false;

  auto clearLocals = [&] {
    locals.clear();
    haveUsageMin = false;
  };
  // The kernel's hid_concatenate_last_usage_page: short usages declared before the last Usage
  // Page item take that page.
  auto concatenateLastPage = [&] {
    for (size_t k = locals.size(); k-- > 0;) {
      if (!locals[k].shortForm) continue;
      if ((locals[k].range.min >> 16) == (g.usagePage & 0xffffu)) break;
      locals[k].range.min = complete(g.usagePage, locals[k].range.min);
      locals[k].range.max = complete(g.usagePage, locals[k].range.max);
    }
  };

  size_t i = 0;
  const size_t n = bytes.size();
  while (i < n) {
    const size_t itemStart = i;
    const uint8_t prefix = bytes[i];
    if (prefix == 0xfe) {  // long item: size, tag, data; no long items are defined, so skip
      if (i + 2 >= n) return fail("truncated long item" + at(itemStart));
      const size_t len = bytes[i + 1];
      if (i + 3 + len > n) return fail("long item runs past the end of the descriptor" + at(itemStart));
      i += 3 + len;
      continue;
    }
    size_t len = prefix & 3u;
    if (len == 3) len = 4;
    const unsigned type = (prefix >> 2) & 3u;
    const unsigned tag = prefix >> 4;
    if (i + 1 + len > n) return fail("item 0x" + hex2(prefix) + " runs past the end of the descriptor" + at(itemStart));
    uint32_t udata = 0;
    for (size_t k = 0; k < len; ++k) udata |= uint32_t{bytes[i + 1 + k]} << (8 * k);
    int32_t sdata = 0;
    switch (len) {
      case 1: sdata = static_cast<int8_t>(udata); break;
      case 2: sdata = static_cast<int16_t>(udata); break;
      case 4: sdata = static_cast<int32_t>(udata); break;
      default: sdata = 0; break;
    }
    i += 1 + len;

    if (type == 0) {  // main
      concatenateLastPage();
      switch (tag) {
        case 0x8:    // Input
        case 0x9:    // Output
        case 0xb: {  // Feature
          const HidReportType rt = tag == 0x8 ? HidReportType::kInput
                                   : tag == 0x9 ? HidReportType::kOutput
                                                : HidReportType::kFeature;
          if (g.reportSize > kMaxReportSize) {
            return fail("Report Size " + std::to_string(g.reportSize) + " is over " + std::to_string(kMaxReportSize) +
                        " bits" + at(itemStart));
          }
          if (g.reportCount > kMaxReportCount) {
            return fail("Report Count " + std::to_string(g.reportCount) + " is over " +
                        std::to_string(kMaxReportCount) + at(itemStart));
          }
          const uint64_t bits = uint64_t{g.reportSize} * g.reportCount;
          uint64_t& offset = offsets[{static_cast<int>(rt), g.reportId}];
          if (offset + bits > kMaxReportBits) return fail("report " + std::to_string(g.reportId) + " is longer than 16 KiB" + at(itemStart));
          if (bits > 0) {
            HidField f;
            f.type = rt;
            f.reportId = static_cast<uint8_t>(g.reportId);
            f.bitOffset = static_cast<uint32_t>(offset);
            f.size = g.reportSize;
            f.count = g.reportCount;
            f.flags = udata;
            f.logicalMin = g.logicalMin;
            f.logicalMax = g.logicalMax;
            f.physicalMin = g.physicalMin;
            f.physicalMax = g.physicalMax;
            f.unitExponent = g.unitExponent;
            f.unit = g.unit;
            f.collection = open.empty() ? -1 : open.back();
            f.usages.reserve(locals.size());
            for (const auto& u : locals) f.usages.push_back(u.range);
            d.fields.push_back(std::move(f));
          }
          offset += bits;
          break;
        }
        case 0xa: {  // Collection
          if (open.size() >= kMaxCollectionDepth) return fail("collections nested deeper than 64" + at(itemStart));
          HidCollection c;
          c.usage = locals.empty() ? 0 : locals.front().range.min;
          c.type = static_cast<uint8_t>(udata & 0xff);
          c.parent = open.empty() ? -1 : open.back();
          d.collections.push_back(c);
          open.push_back(static_cast<int>(d.collections.size() - 1));
          break;
        }
        case 0xc:  // End Collection
          if (open.empty()) return fail("End Collection without an open Collection" + at(itemStart));
          open.pop_back();
          break;
        default:
          d.warnings.push_back("unknown main item tag " + std::to_string(tag) + at(itemStart));
          break;
      }
      clearLocals();
    } else if (type == 1) {  // global
      switch (tag) {
        case 0x0: g.usagePage = udata & 0xffffu; break;
        case 0x1: g.logicalMin = sdata; break;
        case 0x2: g.logicalMax = g.logicalMin < 0 ? sdata : static_cast<int32_t>(udata); break;
        case 0x3: g.physicalMin = sdata; break;
        case 0x4: g.physicalMax = g.physicalMin < 0 ? sdata : static_cast<int32_t>(udata); break;
        case 0x5:  // a 4-bit signed nibble in practice (13 is -3), else the plain value
          g.unitExponent = (udata & ~0xfu) == 0 ? ((udata & 0x8u) ? static_cast<int32_t>(udata) - 16 : static_cast<int32_t>(udata)) : sdata;
          break;
        case 0x6: g.unit = udata; break;
        case 0x7: g.reportSize = udata; break;
        case 0x8:
          if (udata == 0 || udata > 255) return fail("Report ID " + std::to_string(udata) + " is invalid (must be 1..255)" + at(itemStart));
          g.reportId = udata;
          d.usesReportIds = true;
          break;
        case 0x9: g.reportCount = udata; break;
        case 0xa:
          if (globalStack.size() >= kMaxGlobalStack) return fail("Push nested deeper than 32" + at(itemStart));
          globalStack.push_back(g);
          break;
        case 0xb:
          if (globalStack.empty()) return fail("Pop without Push" + at(itemStart));
          g = globalStack.back();
          globalStack.pop_back();
          break;
        default:
          d.warnings.push_back("unknown global item tag " + std::to_string(tag) + at(itemStart));
          break;
      }
    } else if (type == 2) {  // local
      switch (tag) {
        case 0x0: {
          LocalUsage u;
          u.shortForm = len <= 2;
          const uint32_t v = u.shortForm ? complete(g.usagePage, udata) : udata;
          u.range = {v, v};
          if (locals.size() < kMaxReportCount) locals.push_back(u);
          break;
        }
        case 0x1:
          usageMin = udata;
          haveUsageMin = true;
          usageMinShort = len <= 2;
          break;
        case 0x2: {
          LocalUsage u;
          u.shortForm = len <= 2;
          uint32_t lo = haveUsageMin ? usageMin : 0;
          uint32_t hi = udata;
          if (u.shortForm) {
            lo = complete(g.usagePage, lo);
            hi = complete(g.usagePage, hi);
          } else if (usageMinShort && haveUsageMin) {
            lo = (hi & 0xffff0000u) | (lo & 0xffffu);
          }
          haveUsageMin = false;
          if (lo > hi) {
            d.warnings.push_back("Usage Minimum above Usage Maximum" + at(itemStart));
            break;
          }
          u.range = {lo, hi};
          if (locals.size() < kMaxReportCount) locals.push_back(u);
          break;
        }
        case 0xa:
          if (!warnedDelimiter) d.warnings.push_back("Delimiter items ignored (all alternative usages kept)");
          warnedDelimiter = true;
          break;
        default:
          break;  // designators and strings: not needed
      }
    } else {
      d.warnings.push_back("reserved item type" + at(itemStart));
    }
  }
  if (!open.empty()) d.warnings.push_back(std::to_string(open.size()) + " collection(s) left open at the end");
  return d;
}

std::optional<uint32_t> hidExtractBits(std::span<const uint8_t> data, uint32_t bit, uint32_t size) {
  if (size == 0 || size > 32) return std::nullopt;
  if (uint64_t{bit} + size > uint64_t{data.size()} * 8) return std::nullopt;
  uint32_t v = 0;
  for (uint32_t k = 0; k < size; ++k) {
    const uint64_t b = uint64_t{bit} + k;
    if ((data[static_cast<size_t>(b >> 3)] >> (b & 7)) & 1u) v |= 1u << k;
  }
  return v;
}

std::optional<int64_t> hidExtractValue(std::span<const uint8_t> data, const HidValueLoc& loc) {
  const auto raw = hidExtractBits(data, loc.bit, loc.size);
  if (!raw) return std::nullopt;
  int64_t v = *raw;
  if (loc.min < 0 && loc.size < 64 && (v >> (loc.size - 1)) & 1) v -= int64_t{1} << loc.size;
  return v;
}

std::string PenLayout::describe() const {
  std::string s = "report " + std::to_string(reportId) + ":";
  auto add = [&](const char* name, const std::optional<HidValueLoc>& v, bool range) {
    if (!v) return;
    s += std::string(" ") + name + "@" + std::to_string(v->bit);
    if (v->size != 1) s += "/" + std::to_string(v->size);
    if (range) s += " (" + std::to_string(v->min) + ".." + std::to_string(v->max) + ")";
  };
  add("x", x, true);
  add("y", y, true);
  add("pressure", pressure, true);
  add("tip", tip, false);
  add("in_range", inRange, false);
  add("barrel", barrel1, false);
  add("barrel2", barrel2, false);
  add("eraser", eraser, false);
  add("invert", invert, false);
  return s;
}

std::vector<PenLayout> findPens(const HidDescriptor& descriptor) {
  const auto& cols = descriptor.collections;
  std::vector<std::pair<std::pair<uint8_t, int>, PenLayout>> found;  // in order of appearance
  for (const auto& f : descriptor.fields) {
    if (f.type != HidReportType::kInput || f.isConstant() || !f.isVariable()) continue;
    if (f.size == 0 || f.size > 32) continue;
    // Pen context: walk the collections outwards.
    int penCol = -1;
    int appCol = -1;
    bool excluded = false;
    for (int c = f.collection, guard = 0; c >= 0 && c < static_cast<int>(cols.size()) && guard < 128;
         c = cols[static_cast<size_t>(c)].parent, ++guard) {
      const uint32_t u = hidEquivalentUsage(cols[static_cast<size_t>(c)].usage);
      if (u == hidusage::kFinger || u == hidusage::kPuck) excluded = true;
      if (u == hidusage::kStylus && penCol < 0) penCol = c;
      if (cols[static_cast<size_t>(c)].type == 1) appCol = c;
    }
    if (excluded) continue;
    uint32_t app = appCol >= 0 ? hidEquivalentUsage(cols[static_cast<size_t>(appCol)].usage) : 0;
    if (penCol < 0 && (app == hidusage::kPen || app == hidusage::kDigitizer)) penCol = appCol;
    if (penCol < 0) continue;

    const auto key = std::make_pair(f.reportId, penCol);
    auto it = std::find_if(found.begin(), found.end(), [&](const auto& p) { return p.first == key; });
    if (it == found.end()) {
      PenLayout l;
      l.reportId = f.reportId;
      l.reportBits = descriptor.reportBits(HidReportType::kInput, f.reportId);
      l.application = app;
      found.emplace_back(key, l);
      it = std::prev(found.end());
    }
    PenLayout& l = it->second;
    // Walk the usage ranges alongside the values (usageAt(k) for each k would be quadratic).
    size_t range = 0;
    uint64_t within = 0;
    for (uint32_t k = 0; k < f.count; ++k) {
      uint32_t usage = 0;
      if (range < f.usages.size()) {
        usage = f.usages[range].min + static_cast<uint32_t>(within);
        if (++within > uint64_t{f.usages[range].max} - f.usages[range].min) {
          ++range;
          within = 0;
        }
      } else if (!f.usages.empty()) {
        usage = f.usages.back().max;
      }
      std::optional<HidValueLoc>* slot = nullptr;
      switch (hidEquivalentUsage(usage)) {
        case hidusage::kX: slot = &l.x; break;
        case hidusage::kY: slot = &l.y; break;
        case hidusage::kTipPressure: slot = &l.pressure; break;
        case hidusage::kTipSwitch: slot = &l.tip; break;
        case hidusage::kInRange: slot = &l.inRange; break;
        case hidusage::kBarrelSwitch: slot = &l.barrel1; break;
        case hidusage::kSecondaryBarrelSwitch: slot = &l.barrel2; break;
        case hidusage::kEraser: slot = &l.eraser; break;
        case hidusage::kInvert: slot = &l.invert; break;
        default: break;
      }
      if (slot && !*slot) *slot = HidValueLoc{f.bitOffset + k * f.size, f.size, f.logicalMin, f.logicalMax};
    }
  }
  std::vector<PenLayout> pens;
  for (auto& [key, l] : found) {
    if (l.x && l.y) pens.push_back(std::move(l));
  }
  return pens;
}

}  // namespace emboss
