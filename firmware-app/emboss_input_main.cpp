// emboss-input: the tablet diagnostic tool (describe descriptors, decode captures, list and monitor tablets).
#include <poll.h>
#include <signal.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <atomic>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "input/evemu.h"
#include "input/hid_descriptor.h"
#include "input/hidrecord.h"
#include "pen/pen_probe.h"
#include "pen/pen_replay.h"
#include "version.h"

namespace {

constexpr int kExitOk = 0;
constexpr int kExitFailure = 1;
constexpr int kExitUsage = 2;

std::atomic<bool> gStop{false};

void onSignal(int) { gStop = true; }

void printSample(const emboss::PenSample& s) {
  std::printf("%.6f %.5f %.5f %.5f %d %d\n", s.time_s, s.x, s.y, s.pressure, s.tip ? 1 : 0, s.inRange ? 1 : 0);
}

nlohmann::ordered_json locJson(const std::optional<emboss::HidValueLoc>& loc) {
  if (!loc) return nullptr;
  return {{"bit", loc->bit}, {"size", loc->size}, {"max", loc->max}};
}

int describe(const std::string& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) {
    std::fprintf(stderr, "emboss-input: cannot read %s: no such file or no permission\n", file.c_str());
    return kExitFailure;
  }
  const std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  auto d = emboss::parseHidDescriptor(bytes);
  if (!d) {
    std::fprintf(stderr, "emboss-input: %s: %s\n", file.c_str(), d.error().c_str());
    return kExitFailure;
  }
  for (const auto& w : d->warnings) std::fprintf(stderr, "emboss-input: %s: note: %s\n", file.c_str(), w.c_str());
  nlohmann::ordered_json pens = nlohmann::ordered_json::array();
  for (const auto& p : emboss::findPens(*d)) {
    pens.push_back({{"report_id", p.reportId},
                    {"x", locJson(p.x)},
                    {"y", locJson(p.y)},
                    {"pressure", locJson(p.pressure)},
                    {"tip", locJson(p.tip)},
                    {"in_range", locJson(p.inRange)}});
  }
  if (pens.empty()) std::fprintf(stderr, "emboss-input: %s describes no pen (digitizer stylus with X and Y)\n", file.c_str());
  std::cout << nlohmann::ordered_json{{"pens", pens}}.dump() << "\n";
  return kExitOk;
}

int decodeHidrecord(const std::string& file) {
  auto rec = emboss::loadHidRecord(file);
  if (!rec) {
    std::fprintf(stderr, "emboss-input: %s\n", rec.error().c_str());
    return kExitFailure;
  }
  auto samples = emboss::decodeHidRecording(*rec);
  if (!samples) {
    std::fprintf(stderr, "emboss-input: %s: %s\n", file.c_str(), samples.error().c_str());
    return kExitFailure;
  }
  for (const auto& s : *samples) printSample(s);
  return kExitOk;
}

int decodeEvemu(const std::string& file, const std::string& desc) {
  std::optional<std::filesystem::path> d;
  if (!desc.empty()) d = desc;
  auto rec = emboss::loadEvemu(file, d);
  if (!rec) {
    std::fprintf(stderr, "emboss-input: %s\n", rec.error().c_str());
    return kExitFailure;
  }
  auto samples = emboss::evemuToSamples(*rec);
  if (!samples) {
    std::fprintf(stderr, "emboss-input: %s: %s\n", file.c_str(), samples.error().c_str());
    return kExitFailure;
  }
  for (const auto& s : *samples) printSample(s);
  return kExitOk;
}

int list() {
  const auto reports = emboss::probeTablets();
  bool any = false;
  for (const auto& r : reports) {
    char id[16] = "";
    if (r.vendorId || r.productId) std::snprintf(id, sizeof id, "%04x:%04x", r.vendorId, r.productId);
    std::printf("%-6s %-20s %-9s %s\n    %s: %s\n", r.backend.c_str(), r.path.c_str(), id, r.name.c_str(),
                r.usable ? "usable" : "unusable", r.detail.c_str());
    any = any || r.usable;
  }
  if (!any) std::printf("no tablets found\n");
  return kExitOk;
}

int monitor(double seconds) {
  auto pen = emboss::openFirstTablet();
  if (!pen) {
    std::fprintf(stderr, "emboss-input: %s\n", pen.error().c_str());
    return kExitFailure;
  }
  std::fprintf(stderr, "emboss-input: monitoring %s (Ctrl-C stops)\n", (*pen)->name().c_str());
  struct sigaction sa {};
  sa.sa_handler = onSignal;
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
  const double start = emboss::monotonicSeconds();
  std::vector<emboss::PenSample> samples;
  while (!gStop && (seconds <= 0 || emboss::monotonicSeconds() - start < seconds)) {
    const int fd = (*pen)->fd();
    if (fd >= 0) {
      pollfd p{fd, POLLIN, 0};
      ::poll(&p, 1, 100);
    } else {
      ::usleep(5000);
    }
    samples.clear();
    if (!(*pen)->poll(samples)) {
      std::fprintf(stderr, "emboss-input: the tablet is gone\n");
      return kExitFailure;
    }
    for (const auto& s : samples) printSample(s);
    std::fflush(stdout);
  }
  return kExitOk;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"emboss-input: the tablet side of the emboss kiosk (descriptors, captures, live tablets).\n"
               "Samples print one a line: time x y pressure tip in_range (x, y, pressure 0..1; tip, in_range 0/1).\n"
               "Exit codes: 0 ok, 1 failure, 2 bad usage."};
  app.require_subcommand(1);
  app.set_version_flag("--version", std::string("emboss-input ") + emboss::versionString());

  std::string descriptorFile;
  auto* describeCmd = app.add_subcommand(
      "describe",
      "Print the pens a HID report descriptor describes, as JSON: "
      "{\"pens\":[{\"report_id\":N,\"x\":{\"bit\":B,\"size\":S,\"max\":M},\"y\":..,\"pressure\":..,\"tip\":..,\"in_range\":..}]}. "
      "Bit offsets count after the report-ID byte; a field the pen lacks is null.");
  describeCmd->add_option("--descriptor", descriptorFile, "raw report descriptor (e.g. a .hid.bin or sysfs report_descriptor)")
      ->required();

  std::string hidrecordFile;
  auto* decodeCmd = app.add_subcommand("decode", "Decode a hid-recorder capture into pen samples");
  decodeCmd->add_option("--hidrecord", hidrecordFile, "hid-recorder capture (R:, N:, I:, E: lines)")->required();

  std::string evemuFile;
  std::string descFile;
  auto* evemuCmd = app.add_subcommand("evemu", "Decode an evemu recording into pen samples");
  evemuCmd->add_option("file", evemuFile, "evemu .events recording")->required();
  evemuCmd->add_option("--desc", descFile,
                       "the device's .desc when the recording lacks its description (default: found beside the recording)");

  auto* listCmd = app.add_subcommand("list", "List input devices, the back end each would use, and why a device is unusable");

  double seconds = 0.0;
  auto* monitorCmd = app.add_subcommand("monitor", "Print live samples from the first usable tablet (exit 1 when there is none)");
  monitorCmd->add_option("--seconds", seconds, "stop after this many seconds (default: until Ctrl-C)");

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e) == 0 ? kExitOk : kExitUsage;
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e) == 0 ? kExitOk : kExitUsage;
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e) == 0 ? kExitOk : kExitUsage;
  } catch (const CLI::ParseError& e) {
    app.exit(e);
    return kExitUsage;
  }

  if (*describeCmd) return describe(descriptorFile);
  if (*decodeCmd) return decodeHidrecord(hidrecordFile);
  if (*evemuCmd) return decodeEvemu(evemuFile, descFile);
  if (*listCmd) return list();
  if (*monitorCmd) return monitor(seconds);
  return kExitUsage;
}
