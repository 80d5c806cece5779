// HIL: a pen tablet as a uhid device with each real report descriptor of the fixtures; hidapi must
// enumerate it, the raw back end (HidrawPen through pen_probe's decoder choice) must decode the
// strokes fed to it, and destroying and recreating the device must be noticed and recovered within
// two seconds.
//
//   hil_hidraw_uhid [HID_FIXTURE_DIR]     (the fixtures' hid/ folder)
//
// Each non-empty descriptor for which makePenDecoder finds a pen becomes a uhid device with the bus,
// vendor and product of its file name ("0003:256C:006D.0005.hid.bin"). Reports: a synthetic stroke
// (hover, a pressure ramp across the pad, lift, out of range) written into the descriptor's pen
// layout; for the Wacom PenPartner (a fixed-packet model without a pen in its descriptor) the real
// hid-recorder capture beside it. Without the evdev module loaded (as hil-tests.sh runs it) there is
// no evdev node, so openFirstTablet must take the hidraw path too.
#include <cstdio>
#include <algorithm>
#include <map>

#include "hil_common.h"
#include "input/hid_decode.h"
#include "input/hid_descriptor.h"
#include "input/hidrecord.h"
#include "pen/pen_evdev.h"
#include "pen/pen_hidraw.h"
#include "pen/pen_probe.h"

namespace fs = std::filesystem;
using emboss::PenSample;

namespace {

struct Fixture {
  fs::path file;
  std::string label;  // "Huion_H640P/0003:256C:006D.0005"
  uint16_t bus = 0, vendor = 0, product = 0;
  std::vector<uint8_t> descriptor;
  std::optional<fs::path> capture;  // a hid-recorder capture of this very device
};

void setBits(std::vector<uint8_t>& data, uint32_t bit, uint32_t size, int64_t value) {
  for (uint32_t i = 0; i < size; ++i) {
    const uint32_t b = bit + i;
    if (b / 8 >= data.size()) return;
    if ((static_cast<uint64_t>(value) >> i) & 1u) data[b / 8] |= static_cast<uint8_t>(1u << (b % 8));
    else data[b / 8] &= static_cast<uint8_t>(~(1u << (b % 8)));
  }
}

struct Pose {
  double x, y, pressure;
  bool tip, inRange;
};

// One input report of `pen` carrying the pose (report ID byte first when the descriptor numbers reports).
std::vector<uint8_t> encode(const emboss::PenLayout& pen, bool usesReportIds, const Pose& p) {
  const size_t dataBytes = (pen.reportBits + 7) / 8;
  std::vector<uint8_t> r(dataBytes + (usesReportIds ? 1 : 0), 0);
  const uint32_t base = usesReportIds ? 8 : 0;
  if (usesReportIds) r[0] = pen.reportId;
  auto put = [&](const std::optional<emboss::HidValueLoc>& loc, double f) {
    if (!loc) return;
    const int64_t v = loc->min + static_cast<int64_t>(std::llround(f * (static_cast<double>(loc->max) - loc->min)));
    setBits(r, base + loc->bit, loc->size, v);
  };
  put(pen.x, p.x);
  put(pen.y, p.y);
  put(pen.pressure, p.tip ? p.pressure : 0.0);
  put(pen.tip, p.tip ? 1.0 : 0.0);
  put(pen.inRange, p.inRange ? 1.0 : 0.0);
  return r;
}

std::vector<Pose> stroke() {
  std::vector<Pose> poses;
  for (int i = 0; i < 4; ++i) poses.push_back({0.10 + 0.02 * i, 0.30, 0.0, false, true});
  for (int i = 0; i <= 30; ++i) {
    const double f = i / 30.0;
    poses.push_back({0.20 + 0.6 * f, 0.30 + 0.4 * f, 0.1 + 0.8 * f, true, true});
  }
  for (int i = 0; i < 3; ++i) poses.push_back({0.80, 0.70 - 0.02 * i, 0.0, false, true});
  poses.push_back({0.80, 0.66, 0.0, false, false});
  return poses;
}

bool same(const PenSample& a, const PenSample& b) {
  return a.x == b.x && a.y == b.y && a.pressure == b.pressure && a.tip == b.tip && a.inRange == b.inRange &&
         a.barrel1 == b.barrel1 && a.barrel2 == b.barrel2;
}

std::vector<PenSample> dedup(const std::vector<PenSample>& in) {
  std::vector<PenSample> out;
  for (const auto& s : in)
    if (out.empty() || !same(out.back(), s)) out.push_back(s);
  return out;
}

std::string show(const PenSample& s) {
  char b[128];
  std::snprintf(b, sizeof b, "x %.4f y %.4f p %.4f tip %d range %d", s.x, s.y, s.pressure, s.tip, s.inRange);
  return b;
}

std::optional<emboss::HidrawDeviceInfo> findHidraw(uint16_t vendor, uint16_t product) {
  auto list = emboss::enumerateHidraw();
  if (!list) return std::nullopt;
  for (const auto& d : *list)
    if (d.vendorId == vendor && d.productId == product) return d;
  return std::nullopt;
}

// The hidraw half of openFirstTablet for one device: descriptor from the node, decoder, open.
emboss::Result<std::unique_ptr<emboss::HidrawPen>> openRaw(const emboss::HidrawDeviceInfo& info) {
  auto desc = emboss::readHidrawDescriptor(info.path);
  if (!desc) return emboss::Error{desc.error()};
  auto decoder = emboss::makePenDecoder(info.vendorId, info.productId, *desc);
  if (!decoder) return emboss::Error{decoder.error()};
  return emboss::HidrawPen::open(info, std::move(*decoder));
}

// Sends one report and polls until the pen has read it (hidraw keeps 64 reports per reader).
void feed(hil::Uhid& dev, emboss::PenSource& pen, const std::vector<uint8_t>& report, std::vector<PenSample>& out, bool& alive) {
  dev.input(report);
  const size_t before = out.size();
  hil::waitFor([&] {
    alive = pen.poll(out) && alive;
    return out.size() > before || !alive;
  }, 0.05, 0.001);
}

void testFixture(const Fixture& fx) {
  const char* label = fx.label.c_str();
  auto parsed = emboss::parseHidDescriptor(fx.descriptor);
  const auto pens = parsed ? emboss::findPens(*parsed) : std::vector<emboss::PenLayout>{};
  auto offlineDecoder = emboss::makePenDecoder(fx.vendor, fx.product, fx.descriptor);
  if (!offlineDecoder) {
    hil::note("%s: skipped, no pen decoder (%s)", label, offlineDecoder.error().c_str());
    return;
  }

  hil::Uhid dev;
  const std::string name = "HIL " + fx.label.substr(0, fx.label.find('/'));
  if (!hil::check(dev.create(name, fx.bus, fx.vendor, fx.product, fx.descriptor), "%s: uhid device created %s", label, dev.error().c_str()))
    return;
  std::optional<emboss::HidrawDeviceInfo> info;
  const bool enumerated = hil::waitFor([&] { return (info = findHidraw(fx.vendor, fx.product)).has_value(); }, 5.0, 0.05);
  if (!hil::check(enumerated, "%s: hidapi enumerates %04x:%04x (%s)", label, fx.vendor, fx.product,
                  info ? info->describe().c_str() : (dev.started() ? "a driver bound but hidapi does not list it" : "no HID driver bound")))
    return;

  auto desc = emboss::readHidrawDescriptor(info->path);
  hil::check(desc && *desc == fx.descriptor, "%s: the report descriptor read back from %s is the fixture's (%zu bytes)", label,
             info->path.c_str(), desc ? desc->size() : 0);

  const auto reports = emboss::probeTablets();
  const auto it = std::find_if(reports.begin(), reports.end(), [&](const emboss::DeviceReport& r) { return r.path == info->path; });
  hil::check(it != reports.end() && it->usable, "%s: probeTablets: %s usable (%s)", label, info->path.c_str(),
             it != reports.end() ? it->detail.c_str() : "not listed");

  auto pen = openRaw(*info);
  if (!hil::check(pen.ok(), "%s: HidrawPen::open (%s)", label, pen ? (*pen)->name().c_str() : pen.error().c_str())) return;

  // The reports: the real capture where there is one, else a synthetic stroke in the pen's layout.
  std::vector<std::vector<uint8_t>> sent;
  std::vector<Pose> poses;
  if (fx.capture) {
    auto rec = emboss::loadHidRecord(*fx.capture);
    if (!hil::check(rec.ok(), "%s: capture %s loads", label, fx.capture->c_str())) return;
    for (const auto& r : rec->reports) sent.push_back(r.bytes);
  } else if (!pens.empty()) {
    poses = stroke();
    for (const auto& p : poses) sent.push_back(encode(pens.front(), parsed->usesReportIds, p));
  }
  if (!hil::check(!sent.empty(), "%s: %zu reports to send", label, sent.size())) return;

  std::vector<PenSample> live, expected;
  bool alive = true;
  std::optional<size_t> hover;  // a report that decodes to a pen in range: the replug test sends it
  for (size_t k = 0; k < sent.size(); ++k) {
    feed(dev, **pen, sent[k], live, alive);
    if (auto s = (*offlineDecoder)->decode(sent[k], 0.0)) {
      expected.push_back(*s);
      if (!hover && s->inRange) hover = k;
    }
  }
  hil::check(alive, "%s: the device stays alive while reports flow", label);
  // The back end adds an out-of-range sample on silence for pens without in-range: drop idle extras.
  const auto a = dedup(expected), b = dedup(live);
  size_t i = 0;
  while (i < a.size() && i < b.size() && same(a[i], b[i])) ++i;
  const bool equal = i == a.size() && (b.size() == a.size() || (b.size() == a.size() + 1 && !b.back().inRange));
  hil::check(equal, "%s: hidraw samples equal the offline decoding of the same reports (%zu vs %zu%s)", label, a.size(), b.size(),
             equal ? "" : (", first difference at " + std::to_string(i) + ": " + (i < a.size() ? show(a[i]) : "end") + " / " +
                           (i < b.size() ? show(b[i]) : "end")).c_str());
  if (!poses.empty()) {
    // And they are the stroke that was drawn: positions within 1e-3, tip and range as sent.
    size_t tips = 0;
    bool close = true;
    for (const auto& s : live) {
      if (!s.tip) continue;
      ++tips;
      close = close && s.x >= 0.199 && s.x <= 0.801 && s.y >= 0.299 && s.y <= 0.701 && s.pressure > 0.05;
    }
    const bool lifted = !live.empty() && !live.back().tip && !live.back().inRange;
    hil::check(tips >= 25 && close && lifted, "%s: the decoded stroke is the one drawn (%zu tip samples, ends out of range: %d)", label, tips,
               lifted);
  }

  // Unplug: poll() says so. Replug: found and reading again within 2 s.
  dev.destroy();
  bool gone = false;
  hil::waitFor([&] {
    std::vector<PenSample> out;
    return gone = !(*pen)->poll(out);
  }, 2.0, 0.01);
  hil::check(gone, "%s: poll() returns false once the device is destroyed", label);
  pen->reset();

  std::atomic<bool> hovering{true};
  const double t0 = hil::now();
  if (!hil::check(dev.create(name, fx.bus, fx.vendor, fx.product, fx.descriptor), "%s: recreated", label)) return;
  std::thread pulse([&] {  // a pen hovering over the new device: a report every 20 ms
    while (hovering) {
      dev.input(sent[hover.value_or(0)]);
      hil::sleepS(0.02);
    }
  });
  std::unique_ptr<emboss::HidrawPen> again;
  bool sampled = false;
  hil::waitFor([&] {
    if (!again) {
      if (auto i2 = findHidraw(fx.vendor, fx.product))
        if (auto p = openRaw(*i2)) again = std::move(*p);
      return false;
    }
    std::vector<PenSample> out;
    again->poll(out);
    return sampled = !out.empty();
  }, 2.0, 0.05);
  const double took = hil::now() - t0;
  // The kiosk's own probe finds it too (the hidraw path: no evdev node without the evdev module).
  std::unique_ptr<emboss::PenSource> first;
  if (again) {
    again.reset();
    auto f = emboss::openFirstTablet();
    if (f) first = std::move(*f);
  }
  hovering = false;
  pulse.join();
  hil::check(sampled && took < 2.0, "%s: recreated device open and reading again after %.2f s", label, took);
  const bool evdevLoaded = std::filesystem::exists("/sys/module/evdev");
  hil::check(first && (evdevLoaded || first->name().rfind("hidraw:", 0) == 0), "%s: openFirstTablet takes it (%s)", label,
             first ? first->name().c_str() : "nothing");
  first.reset();
  dev.destroy();
  hil::waitFor([&] { return !findHidraw(fx.vendor, fx.product); }, 2.0, 0.05);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s FIXTURES/hid (the folder of the fixtures' hid files)\n", argv[0]);
    return 2;
  }
  const fs::path dir = argv[1];
  std::vector<Fixture> fixtures;
  std::error_code ec;
  for (const auto& folder : fs::directory_iterator(dir, ec)) {
    if (!folder.is_directory()) continue;
    for (const auto& f : fs::directory_iterator(folder.path(), ec)) {
      const std::string fname = f.path().filename().string();
      if (fname.size() < 8 || fname.substr(fname.size() - 8) != ".hid.bin") continue;
      Fixture fx;
      fx.file = f.path();
      fx.label = folder.path().filename().string() + "/" + fname.substr(0, fname.size() - 8);
      unsigned bus = 0, vendor = 0, product = 0;
      if (std::sscanf(fname.c_str(), "%x:%x:%x", &bus, &vendor, &product) != 3) continue;
      fx.bus = static_cast<uint16_t>(bus);
      fx.vendor = static_cast<uint16_t>(vendor);
      fx.product = static_cast<uint16_t>(product);
      fx.descriptor = hil::readBytes(f.path());
      if (fx.descriptor.empty()) {
        hil::note("%s: skipped, empty descriptor", fx.label.c_str());
        continue;
      }
      const fs::path capture = folder.path() / "hidrecord.txt";
      if (fs::exists(capture)) {
        auto rec = emboss::loadHidRecord(capture);
        if (rec && rec->descriptor == fx.descriptor) fx.capture = capture;
      }
      fixtures.push_back(fx);
    }
  }
  std::sort(fixtures.begin(), fixtures.end(), [](const Fixture& a, const Fixture& b) { return a.label < b.label; });
  hil::check(!fixtures.empty(), "found %zu non-empty descriptors in %s", fixtures.size(), dir.c_str());
  for (const auto& fx : fixtures) testFixture(fx);
  return hil::finish("hil_hidraw_uhid");
}
