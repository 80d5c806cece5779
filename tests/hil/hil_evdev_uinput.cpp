// HIL: a pen tablet as a uinput device replaying each evemu recording; the evdev back end
// (EvdevPen::open, probeTablets, openFirstTablet) must read the same strokes as the offline decoder.
//
//   hil_evdev_uinput [EVEMU_DIR]     (the fixtures' evemu/ folder)
//
// The uinput device gets the recording's name, IDs, keys, axes (fuzz 0: a recording holds values the
// kernel already filtered once) and properties. Events are written one frame (up to SYN_REPORT) at a
// time and the back end polled after each, as a live tablet would deliver them. The kernel drops
// repeated values and empty frames, so both sample streams are compared with repeats removed.
#include <cstdio>
#include <linux/input.h>

#include <algorithm>
#include <map>
#include <sstream>

#include "evemu_uinput.h"
#include "hil_common.h"
#include "input/evemu.h"
#include "pen/pen_evdev.h"
#include "pen/pen_probe.h"

namespace fs = std::filesystem;
using emboss::PenSample;
using hil::parseProps;
using hil::specFor;

namespace {

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
  char b[160];
  std::snprintf(b, sizeof b, "x %.5f y %.5f p %.4f tip %d range %d b1 %d b2 %d", s.x, s.y, s.pressure, s.tip, s.inRange,
                s.barrel1, s.barrel2);
  return b;
}

// Replays `rec` into the uinput device and collects what the evdev back end reads.
std::vector<PenSample> replay(hil::Uinput& dev, emboss::PenSource& pen, const emboss::EvemuRecording& rec, bool& alive) {
  std::vector<PenSample> live;
  alive = true;
  for (const auto& e : rec.events) {
    dev.emit(e.type, e.code, e.value);
    if (e.type == EV_SYN && e.code == SYN_REPORT) alive = pen.poll(live) && alive;
  }
  alive = pen.poll(live) && alive;
  return live;
}

void testRecording(const fs::path& events) {
  const std::string label = events.filename().string();
  auto rec = emboss::loadEvemu(events);
  if (!hil::check(rec.ok(), "%s: loads (%s)", label.c_str(), rec ? "ok" : rec.error().c_str())) return;
  auto offline = emboss::evemuToSamples(*rec);
  if (!hil::check(offline.ok(), "%s: decodes offline", label.c_str())) return;

  fs::path descFile = events;
  if (rec->device.name.empty() || hil::readFile(events)->find("\nP:") == std::string::npos) {
    if (auto d = emboss::findEvemuDesc(events)) descFile = *d;
  }
  hil::Uinput dev;
  if (!hil::check(dev.create(specFor(rec->device, parseProps(descFile))), "%s: uinput device \"%s\" created %s", label.c_str(),
                  rec->device.name.c_str(), dev.error().c_str()))
    return;

  // probeTablets sees it as a usable evdev tablet.
  const auto reports = emboss::probeTablets();
  const auto it = std::find_if(reports.begin(), reports.end(), [&](const emboss::DeviceReport& r) { return r.path == dev.node(); });
  hil::check(it != reports.end() && it->usable && it->backend == "evdev", "%s: probeTablets lists %s as a usable evdev tablet (%s)",
             label.c_str(), dev.node().c_str(), it != reports.end() ? it->detail.c_str() : "not listed");

  auto pen = emboss::EvdevPen::open(dev.node(), true);
  if (!hil::check(pen.ok(), "%s: EvdevPen::open(%s) (%s)", label.c_str(), dev.node().c_str(), pen ? (*pen)->name().c_str() : pen.error().c_str()))
    return;
  // Grabbed: nobody else can grab it now.
  auto second = emboss::EvdevPen::open(dev.node(), true);
  hil::check(!second.ok(), "%s: a second grab fails while the kiosk holds the tablet (%s)", label.c_str(),
             second ? "it succeeded" : second.error().c_str());

  bool alive = false;
  const double t0 = hil::now();
  auto live = replay(dev, **pen, *rec, alive);
  const double t1 = hil::now();
  hil::check(alive, "%s: the device stays alive during the replay", label.c_str());
  hil::check(!live.empty() && std::all_of(live.begin(), live.end(), [&](const PenSample& s) { return s.time_s >= t0 - 1 && s.time_s <= t1 + 1; }),
             "%s: live samples carry CLOCK_MONOTONIC time stamps (%zu samples)", label.c_str(), live.size());

  const auto a = dedup(*offline), b = dedup(live);
  size_t firstDiff = 0;
  while (firstDiff < a.size() && firstDiff < b.size() && same(a[firstDiff], b[firstDiff])) ++firstDiff;
  const bool equal = a.size() == b.size() && firstDiff == a.size();
  hil::check(equal, "%s: live samples equal the offline decoder's (%zu vs %zu distinct samples%s)", label.c_str(), a.size(), b.size(),
             equal ? "" : (", first difference at " + std::to_string(firstDiff) + ": offline " +
                           (firstDiff < a.size() ? show(a[firstDiff]) : "end") + " / live " + (firstDiff < b.size() ? show(b[firstDiff]) : "end"))
                              .c_str());
  const auto sa = emboss::splitStrokes(*offline), sb = emboss::splitStrokes(live);
  bool strokesEqual = sa.size() == sb.size();
  for (size_t i = 0; strokesEqual && i < sa.size(); ++i) strokesEqual = dedup(sa[i]).size() == dedup(sb[i]).size();
  hil::check(strokesEqual, "%s: same strokes (%zu offline, %zu live)", label.c_str(), sa.size(), sb.size());
}

// Unplug and replug: poll() reports the loss, openFirstTablet finds the tablet again.
void testReplug(const fs::path& events) {
  auto rec = emboss::loadEvemu(events);
  if (!rec) return;
  hil::Uinput dev;
  if (!hil::check(dev.create(specFor(rec->device, {})), "replug: device created")) return;
  auto first = emboss::openFirstTablet();
  if (!hil::check(first.ok(), "replug: openFirstTablet picks the uinput tablet (%s)", first ? (*first)->name().c_str() : first.error().c_str()))
    return;
  hil::check((*first)->name().find(rec->device.name) != std::string::npos, "replug: it is the replayed device (%s)", (*first)->name().c_str());
  dev.destroy();
  std::vector<PenSample> out;
  bool gone = false;
  hil::waitFor([&] { return gone = !(*first)->poll(out); }, 2.0);
  hil::check(gone, "replug: poll() returns false once the device is destroyed");
  auto none = emboss::openFirstTablet();
  hil::check(!none.ok(), "replug: openFirstTablet fails while no tablet is there (%s)", none ? "it found one" : none.error().c_str());
  const double t0 = hil::now();
  if (!hil::check(dev.create(specFor(rec->device, {})), "replug: device created again")) return;
  std::unique_ptr<emboss::PenSource> again;
  hil::waitFor([&] {
    auto p = emboss::openFirstTablet();
    if (p) again = std::move(*p);
    return again != nullptr;
  }, 2.0, 0.1);
  const double took = hil::now() - t0;
  hil::check(again != nullptr && took < 2.0, "replug: the tablet is open again %.2f s after it reappeared", took);
  if (!again) return;
  bool alive = false;
  auto live = replay(dev, *again, *rec, alive);
  hil::check(alive && !dedup(live).empty(), "replug: samples flow after the replug (%zu)", live.size());
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s FIXTURES/evemu (the folder of the fixtures' evemu files)\n", argv[0]);
    return 2;
  }
  const fs::path dir = argv[1];
  std::vector<fs::path> files;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(dir, ec))
    if (e.path().extension() == ".events") files.push_back(e.path());
  std::sort(files.begin(), files.end());
  hil::check(!files.empty(), "found %zu evemu recordings in %s", files.size(), dir.c_str());
  for (const auto& f : files) testRecording(f);
  if (!files.empty()) testReplug(files.front());
  return hil::finish("hil_evdev_uinput");
}
