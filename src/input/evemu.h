// evemu recordings (.desc device descriptions, .events event streams) parsed and turned into PenSamples.
#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "devices/pen.h"
#include "input/evdev_pen_state.h"
#include "util/result.h"

namespace emboss {

struct EvemuEvent {
  double time_s = 0.0;
  int type = 0;
  int code = 0;
  int32_t value = 0;
};

// The device part of an evemu file: N:, I:, B: and A: lines.
struct EvemuDevice {
  std::string name;
  uint16_t bus = 0;
  uint16_t vendor = 0;
  uint16_t product = 0;
  uint16_t version = 0;
  std::map<int, AbsRange> axes;                // A: lines, by ABS_* code
  std::map<int, std::vector<uint8_t>> bits;    // B: lines, capability bytes per event type
  bool hasKey(int code) const;                 // from the EV_KEY bits
  bool hasAxes() const { return !axes.empty(); }
};

struct EvemuRecording {
  EvemuDevice device;
  std::vector<EvemuEvent> events;
};

// Parses evemu text: a .desc, an .events file, or both in one (as evemu-record writes them).
// Comments ('#' to the end of the line) and unknown lines are skipped; malformed A:/E: lines fail
// with their line number.
Result<EvemuRecording> parseEvemu(std::string_view text);

// Reads an .events file; when it has no axis ranges of its own, the description comes from desc,
// or else from the .desc beside it that findEvemuDesc picks.
Result<EvemuRecording> loadEvemu(const std::filesystem::path& events,
                                 const std::optional<std::filesystem::path>& desc = std::nullopt);

// Finds the .desc describing an .events file that lacks its own description. The rule:
//  1. "NAME.desc" beside "NAME.events" wins;
//  2. otherwise, a .desc whose name, less a trailing interface word ("Pen", "Stylus", "Eraser",
//     "Pad", "Finger", "Touch", "Mouse", "Keyboard"), is a word-prefix of the .events name, words
//     being split at spaces, '.', '-' and '_' ("Wacom Intuos4 6x9 Pen.desc" for
//     "Wacom Intuos4 6x9.stylus-tap.events");
//  3. among several, the one matching the most words; on a tie, a "Pen"/"Stylus" one.
// Fails, naming the candidates it saw, when nothing matches.
Result<std::filesystem::path> findEvemuDesc(const std::filesystem::path& events);

// One PenSample per SYN_REPORT (see EvdevPenState for the rules). Fails when the device has no
// ABS_X/ABS_Y range (an .events file without its description).
Result<std::vector<PenSample>> evemuToSamples(const EvemuRecording& recording);

// A stroke: the consecutive samples with the tip down (tip down .. tip up).
using Stroke = std::vector<PenSample>;
std::vector<Stroke> splitStrokes(const std::vector<PenSample>& samples);

}  // namespace emboss
