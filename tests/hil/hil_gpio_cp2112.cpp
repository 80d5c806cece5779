// HIL: the GPIO buttons through a real gpiochip. Debian's kernels have neither gpio-sim nor
// gpio-mockup, but they have hid-cp2112, the driver of Silicon Labs' CP2112 USB-HID to SMBus/GPIO
// bridge, which registers a real gpiochip ("cp2112_gpio", 8 lines) with an interrupt chip. This
// program emulates the CP2112's HID protocol (AN495 feature reports) over uhid, so the kernel's
// driver, gpiolib, the GPIO character device and libgpiod all run for real; the test moves the
// emulated pins and the libgpiod back end (openGpioButtons, GpioButtons::poll) must see the edges,
// debounce them, and map them to actions, long presses and chords.
//
// The CP2112 has no edge interrupt: its driver polls the pin levels every 10 jiffies (40 ms at
// HZ=250) and makes edge interrupts of the changes. Glitches the test makes are therefore 150 ms
// long (several polls even on a loaded machine), and the configuration under test debounces over
// 300 ms; a control run with 20 ms debouncing shows such glitches do come through when the
// debounce is short.
//
// The sequence runs twice: with the lines requested for edge events (read "edges"), then as the
// kiosk reads a chip that can be unplugged (read "auto" gives levels every 20 ms on this HID
// device). The unplug comes last, with only the levels source open, and the kernel's log must not
// say that it freed an interrupt under a handler of ours: Linux 6.1 does that to every line still
// requested for edges when its chip goes away (docs/hardware.md).
//
//   hil_gpio_cp2112          (needs the modules uhid and hid-cp2112)
#include <fcntl.h>
#include <unistd.h>

#include <algorithm>

#include <gpiod.h>

#include "gpio/buttons_gpio.h"
#include "devices/button_config.h"
#include "cp2112.h"
#include "hil_common.h"

namespace {

using emboss::Action;
using emboss::ButtonEvent;

// Polls the source like the kiosk's main loop (every 10 ms) for `seconds`, collecting events.
std::vector<ButtonEvent> pump(emboss::ButtonSource& src, double seconds, bool& alive) {
  std::vector<ButtonEvent> out;
  const double end = hil::now() + seconds;
  alive = true;
  while (hil::now() < end && alive) {
    alive = src.poll(out);
    hil::sleepS(0.01);
  }
  return out;
}

std::string describe(const std::vector<ButtonEvent>& events) {
  std::string s;
  for (const auto& e : events)
    s += std::string(s.empty() ? "" : ", ") + emboss::actionName(e.action) + (e.longPress ? " (long)" : "") + (e.pressed ? " down" : " up");
  return s.empty() ? "none" : s;
}

emboss::ButtonConfig config(const std::string& chip, double debounceS, emboss::GpioRead read = emboss::GpioRead::Auto) {
  emboss::ButtonConfig c;
  c.read = read;
  c.source = "hil config";
  c.longPressS = 1.0;
  c.chordWindowS = 0.3;
  auto add = [&](unsigned line, Action a, Action longPress = Action::None) {
    emboss::ButtonLineConfig b;
    b.chip = chip;
    b.line = line;
    b.action = a;
    b.activeLow = true;
    b.bias = emboss::LineBias::PullUp;
    b.debounceS = debounceS;
    b.longPress = longPress;
    c.buttons.push_back(b);
  };
  add(0, Action::NextTool);
  add(1, Action::Undo);
  add(2, Action::Redo);
  add(3, Action::NewSheet, Action::Staff);
  emboss::ChordConfig chord;
  chord.buttons = {Action::Undo, Action::Redo};
  chord.action = Action::Turn;
  chord.holdS = 0.3;
  c.chords.push_back(chord);
  return c;
}

// Presses, glitches, bounces, a long press, a short press and a chord, each checked; `how` names the
// way the lines are read in every message.
void sequence(emboss::ButtonSource& buttons, hil::Cp2112& chip, const std::string& how) {
  bool alive = true;
  pump(buttons, 0.2, alive);

  // 1. A clean press and release.
  const double t0 = hil::now();
  chip.press(0, true);
  auto ev = pump(buttons, 0.6, alive);
  const auto down = std::find_if(ev.begin(), ev.end(), [](const ButtonEvent& e) { return e.action == Action::NextTool && e.pressed; });
  hil::check(down != ev.end() && ev.size() == 1, "%s: press on line 0 gives next_tool down (%s)", how.c_str(), describe(ev).c_str());
  if (down != ev.end())
    hil::check(down->time_s >= t0 - 0.05 && down->time_s <= t0 + 0.3, "%s: its time stamp is the settled edge's, on CLOCK_MONOTONIC (%.3f s after the press)",
               how.c_str(), down->time_s - t0);
  chip.press(0, false);
  ev = pump(buttons, 0.6, alive);
  hil::check(ev.size() == 1 && ev[0].action == Action::NextTool && !ev[0].pressed, "%s: release gives next_tool up (%s)", how.c_str(), describe(ev).c_str());

  // 2. A glitch shorter than the debounce: nothing.
  chip.press(0, true);
  hil::sleepS(0.15);
  chip.press(0, false);
  ev = pump(buttons, 0.6, alive);
  hil::check(ev.empty(), "%s: a 150 ms glitch on line 0 is debounced away (%s)", how.c_str(), describe(ev).c_str());

  // 3. A bouncing press and a bouncing release: one press, one release.
  for (int i = 0; i < 2; ++i) {
    chip.press(1, true);
    hil::sleepS(0.15);
    chip.press(1, false);
    hil::sleepS(0.15);
  }
  chip.press(1, true);
  hil::sleepS(0.8);
  chip.press(1, false);
  hil::sleepS(0.15);
  chip.press(1, true);
  hil::sleepS(0.15);
  chip.press(1, false);
  ev = pump(buttons, 0.8, alive);
  // undo is a chord member: its press waits for the chord window, then goes out on its own.
  const auto undoDown = std::count_if(ev.begin(), ev.end(), [](const ButtonEvent& e) { return e.action == Action::Undo && e.pressed; });
  const auto undoUp = std::count_if(ev.begin(), ev.end(), [](const ButtonEvent& e) { return e.action == Action::Undo && !e.pressed; });
  hil::check(undoDown == 1 && undoUp == 1, "%s: a bouncing press and release on line 1 gives one undo down and one undo up (%s)", how.c_str(),
             describe(ev).c_str());

  // 4. A long press: new_sheet held for 1.4 s gives staff (long) instead.
  chip.press(3, true);
  hil::sleepS(1.4);
  chip.press(3, false);
  ev = pump(buttons, 0.6, alive);
  const bool longStaff = std::any_of(ev.begin(), ev.end(), [](const ButtonEvent& e) { return e.action == Action::Staff && e.longPress; });
  const bool shortSheet = std::any_of(ev.begin(), ev.end(), [](const ButtonEvent& e) { return e.action == Action::NewSheet; });
  hil::check(longStaff && !shortSheet, "%s: holding line 3 for 1.4 s gives the long-press action staff, not new_sheet (%s)", how.c_str(),
             describe(ev).c_str());

  // 5. A short press of the same button: its own action.
  chip.press(3, true);
  hil::sleepS(0.45);
  chip.press(3, false);
  ev = pump(buttons, 0.6, alive);
  hil::check(std::any_of(ev.begin(), ev.end(), [](const ButtonEvent& e) { return e.action == Action::NewSheet && e.pressed; }) &&
                 std::none_of(ev.begin(), ev.end(), [](const ButtonEvent& e) { return e.action == Action::Staff; }),
             "%s: a short press on line 3 gives new_sheet (%s)", how.c_str(), describe(ev).c_str());

  // 6. A chord: undo and redo pressed together and held gives turn, and neither of their own.
  chip.press(1, true);
  hil::sleepS(0.05);
  chip.press(2, true);
  hil::sleepS(0.9);
  chip.press(1, false);
  chip.press(2, false);
  ev = pump(buttons, 0.6, alive);
  const bool turn = std::any_of(ev.begin(), ev.end(), [](const ButtonEvent& e) { return e.action == Action::Turn && e.pressed; });
  const bool own = std::any_of(ev.begin(), ev.end(), [](const ButtonEvent& e) { return e.action == Action::Undo || e.action == Action::Redo; });
  hil::check(turn && !own, "%s: undo + redo held together give the chord's turn (%s)", how.c_str(), describe(ev).c_str());
  hil::check(alive, "%s: the source stayed alive throughout", how.c_str());
}

}  // namespace

int main() {
  hil::Cp2112 chip;
  const std::string name = hil::startCp2112(chip);
  if (name.empty()) return hil::finish("hil_gpio_cp2112");
  const auto chips = emboss::listGpioChips();
  hil::check(std::find(chips.begin(), chips.end(), "/dev/" + name) != chips.end(), "listGpioChips lists /dev/%s", name.c_str());

  // A line the chip does not have: a clear failure.
  {
    auto c = config(name, 0.3);
    c.buttons[0].line = 9;
    auto bad = emboss::openGpioButtons(c);
    hil::check(!bad && bad.error().find("does not exist") != std::string::npos, "openGpioButtons refuses line 9 of an 8-line chip (%s)",
               bad ? "it opened" : bad.error().c_str());
    auto c2 = config("gpiochip99", 0.3);
    auto none = emboss::openGpioButtons(c2);
    hil::check(!none, "openGpioButtons refuses a chip that is not there (%s)", none ? "it opened" : none.error().c_str());
  }

  // Control: with a 20 ms debounce, a 100 ms glitch is a press.
  {
    auto buttons = emboss::openGpioButtons(config(name, 0.02));
    if (hil::check(buttons.ok(), "openGpioButtons (20 ms debounce): %s", buttons ? (*buttons)->name().c_str() : buttons.error().c_str())) {
      bool alive = true;
      pump(**buttons, 0.2, alive);
      chip.press(0, true);
      hil::sleepS(0.15);
      chip.press(0, false);
      auto ev = pump(**buttons, 0.5, alive);
      const bool seen = std::count_if(ev.begin(), ev.end(), [](const ButtonEvent& e) { return e.action == Action::NextTool && e.pressed; }) == 1;
      hil::check(seen, "control: a 150 ms pulse on line 0 reaches the back end as a press when debouncing is 20 ms (%s)", describe(ev).c_str());
    }
  }

  hil::check(emboss::gpioChipIsRemovable(name), "gpioChipIsRemovable(%s): the emulated CP2112 is a HID device, so it can be unplugged", name.c_str());

  // The sequence with edge events (by label, as gpiodetect shows it), then closed.
  {
    auto edges = emboss::openGpioButtons(config("cp2112_gpio", 0.3, emboss::GpioRead::Edges));
    if (hil::check(edges.ok(), "openGpioButtons by chip label, read as edges (300 ms debounce): %s",
                   edges ? (*edges)->name().c_str() : edges.error().c_str()))
      sequence(**edges, chip, "edges");
  }

  // The same as the kiosk reads this chip: levels.
  auto opened = emboss::openGpioButtons(config("cp2112_gpio", 0.3));
  if (!hil::check(opened.ok(), "openGpioButtons by chip label, read as it chooses (300 ms debounce): %s",
                  opened ? (*opened)->name().c_str() : opened.error().c_str()))
    return hil::finish("hil_gpio_cp2112");
  auto& buttons = **opened;
  hil::check(buttons.name().find("levels every 20 ms") != std::string::npos, "read \"auto\" reads a removable chip's levels (%s)", buttons.name().c_str());
  sequence(buttons, chip, "levels");
  hil::note("the driver read the pin levels %d times", chip.levelReads());

  // 7. Unplugged: the source says so, and the kernel freed no interrupt under a handler of ours.
  // Its log is read from /dev/kmsg, from here on.
  const int kmsg = ::open("/dev/kmsg", O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  if (kmsg >= 0) ::lseek(kmsg, 0, SEEK_END);
  const double unplugged = hil::now();
  chip.destroy();
  bool gone = false;
  hil::waitFor([&] {
    std::vector<ButtonEvent> out;
    return gone = !buttons.poll(out);
  }, 3.0, 0.02);
  hil::check(gone, "poll() returns false once the GPIO adapter is unplugged (after %.2f s)", hil::now() - unplugged);
  opened->reset();
  if (kmsg >= 0) {
    std::string leaked;
    char record[8192];
    for (;;) {
      const ssize_t n = ::read(kmsg, record, sizeof record);
      if (n < 0 && errno == EPIPE) continue;  // records overwritten while we read: go on with the next
      if (n <= 0) break;
      const std::string line(record, static_cast<size_t>(n));
      if (line.find("leaking at least") != std::string::npos) leaked += line;
    }
    ::close(kmsg);
    hil::check(leaked.empty(), "the kernel freed no interrupt under a handler of ours at the unplug (%s)",
               leaked.empty() ? "its log says nothing of it" : leaked.c_str());
  } else {
    hil::note("cannot read /dev/kmsg (%s): the kernel's log at the unplug is not checked", std::strerror(errno));
  }
  return hil::finish("hil_gpio_cp2112");
}
