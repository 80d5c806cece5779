// Buttons: the kiosk's few big hardware buttons (GPIO) or the keyboard standing in for them.
#pragma once

#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "devices/poll_pace.h"

namespace emboss {

// What a button does. The mapping from a physical line or key to an action is configuration.
enum class Action {
  None,
  NextTool,
  PrevTool,
  SizeUp,
  SizeDown,
  NextMetal,
  Undo,
  Redo,
  Turn,      // turn the workpiece (the paper's rotation); pressed again: back
  NewSheet,
  Capture,   // photograph a drawing on paper: its lines become a guide on the plate (docs/kiosk.md)
  Staff,     // a chord or long press of configured buttons enters staff mode
  Quit,      // development only (keyboard)
};

const char* actionName(Action a);
Action actionFromName(const std::string& name);  // Action::None when unknown

struct ButtonEvent {
  double time_s = 0.0;
  Action action = Action::None;
  bool pressed = true;  // false on release
  bool longPress = false;
};

class ButtonSource {
 public:
  virtual ~ButtonSource() = default;
  virtual std::string name() const = 0;
  // Appends the events available now; false when the device is gone.
  virtual bool poll(std::vector<ButtonEvent>& out) = 0;
  virtual int fd() const { return -1; }
  // Within how many seconds from now poll() must be called again when fd() has not become readable
  // meanwhile: never (infinity) for a source with a descriptor and nothing pending, kPollPaceS for
  // one that must be polled; GPIO buttons know their debounce and long-press deadlines.
  virtual double pollWithin() const { return fd() >= 0 ? std::numeric_limits<double>::infinity() : kPollPaceS; }
};

// Button events handed in by the program itself (the soak benchmark, tests), taken at the next poll.
class QueuedButtons final : public ButtonSource {
 public:
  explicit QueuedButtons(std::string name = "queued buttons") : name_(std::move(name)) {}
  std::string name() const override { return name_; }
  bool poll(std::vector<ButtonEvent>& out) override {
    out.insert(out.end(), queued.begin(), queued.end());
    queued.clear();
    return true;
  }
  // A short press and release of `a` at time t.
  void tap(Action a, double t) {
    queued.push_back({t, a, true, false});
    queued.push_back({t, a, false, false});
  }
  std::vector<ButtonEvent> queued;

 private:
  std::string name_;
};

}  // namespace emboss
