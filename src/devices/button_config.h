// Button configuration: which GPIO line is which button, its polarity, bias, debounce and gestures.
#pragma once

#include <array>
#include <filesystem>
#include <string>
#include <vector>

#include "devices/buttons.h"
#include "util/result.h"

namespace emboss {

// The line's internal resistor, if the chip has one (Linux 5.5 and later can set it).
enum class LineBias { AsIs, Disable, PullUp, PullDown };

const char* lineBiasName(LineBias b);

// How the lines are read. Edges: the kernel's edge events (an interrupt per line, stamped by the
// kernel). Levels: the levels read every 20 ms, with no interrupt held. Auto: levels on a chip that
// can be unplugged (on USB or HID, such as a CP2112 adapter), edges on any other (a board's own
// header). Linux 6.1 frees a removed chip's interrupts under the handlers of the lines still
// requested for edges (docs/hardware.md, "Unplugging a USB GPIO adapter").
enum class GpioRead { Auto, Edges, Levels };

const char* gpioReadName(GpioRead r);

// One physical button on one GPIO line.
struct ButtonLineConfig {
  std::string chip = "gpiochip0";  // a chip name, number, /dev path or label (as gpiodetect shows)
  unsigned line = 0;               // the line offset on that chip (on a Raspberry Pi: the BCM number)
  Action action = Action::None;
  bool activeLow = true;           // pressed pulls the line to ground (pull-up wiring)
  LineBias bias = LineBias::PullUp;
  double debounceS = 0.020;        // the level must stay this long before it counts
  // When not None: held for ButtonConfig::longPressS, the button emits this action (longPress set)
  // instead of its own; a shorter press emits its own action on release.
  Action longPress = Action::None;
};

// Two buttons pressed together (within ButtonConfig::chordWindowS of each other) emit `action`
// instead of their own actions. With holdS > 0 both must stay held that long; released earlier,
// the chord does nothing.
struct ChordConfig {
  std::array<Action, 2> buttons{Action::None, Action::None};
  Action action = Action::Staff;
  double holdS = 0.0;
};

struct ButtonConfig {
  std::vector<ButtonLineConfig> buttons;
  std::vector<ChordConfig> chords;
  double longPressS = 3.0;
  double chordWindowS = 0.15;
  GpioRead read = GpioRead::Auto;
  std::string source = "built-in";  // where the configuration came from, for messages

  // The index of the button with this action, or -1.
  int buttonFor(Action a) const;
};

// Parses the JSON format of docs/hardware.md; `name` prefixes every message
// ("buttons.json: buttons[2].action: unknown action 'nxt_tool' ...").
Result<ButtonConfig> parseButtonConfig(const std::string& text, const std::string& name = "buttons.json");
Result<ButtonConfig> loadButtonConfig(const std::filesystem::path& path);

// The wiring that docs/hardware.md suggests for a Raspberry Pi header (gpiochip0, BCM numbers):
// ten buttons, new_sheet held 3 s and undo + redo held together 1 s enter staff mode.
ButtonConfig defaultButtonConfig();

}  // namespace emboss
