// Button gestures: raw edges of button lines to debounced presses, long presses and chords.
#pragma once

#include <optional>
#include <vector>

#include "devices/button_config.h"
#include "devices/buttons.h"

namespace emboss {

// Portable and clock-free: times are seconds on one monotonic clock, given by the caller (the GPIO
// back end passes the kernel's edge time stamps; tests pass a fake clock). Events come out in the
// order their deadlines fall, whatever the caller's polling cadence.
//
// Debounce: a level counts once it has stayed for the button's debounceS; a glitch shorter than
// that is ignored. Press events are stamped with the time the level settled (its last edge).
// Long press: a button with longPress set emits nothing on press; released before longPressS it
// emits its own press and release, held that long it emits longPress (ButtonEvent::longPress).
// Chord: a chord member's press waits up to chordWindowS for its partner; both pressed within the
// window emit the chord's action (after holdS, when set) and nothing of their own.
// Thread-safety: one thread uses an instance.
class ButtonGestures {
 public:
  explicit ButtonGestures(const ButtonConfig& config);

  size_t size() const { return buttons_.size(); }
  // The level at start, without an event. A button already pressed is ignored until released.
  void reset(size_t button, bool pressed, double t);
  // The line's logical level (true: pressed) from time t on. Edges come in time order; a repeated
  // level (an opposite edge was lost) restarts the debounce time.
  void edge(size_t button, bool pressed, double t, std::vector<ButtonEvent>& out);
  // Advances to time t: settles levels, fires long presses, lapses chord windows.
  void advance(double t, std::vector<ButtonEvent>& out);
  // When advance() next has something to do, or nullopt when nothing is pending.
  std::optional<double> nextDeadline() const;
  // The debounced level.
  bool pressed(size_t button) const { return buttons_[button].stable; }

 private:
  enum class Phase { Idle, Pending, Pressed, Held, Chord, Ignored };
  struct Button {
    Action action = Action::None;
    Action longPress = Action::None;
    double debounceS = 0.0;
    int chord = -1;
    bool raw = false;
    double rawT = 0.0;
    bool stable = false;
    Phase phase = Phase::Idle;
    double pressT = 0.0;
  };
  struct Chord {
    Action action = Action::Staff;
    double holdS = 0.0;
    size_t a = 0, b = 0;
    bool active = false;  // both members pressed together, chord not yet released
    bool fired = false;   // its press event went out
    double startT = 0.0;
  };

  // The earliest pending deadline and what it is (button index, or chord index + size()).
  std::optional<double> deadline(size_t* which) const;
  double buttonDeadline(const Button& b) const;
  void fire(size_t which, double t, std::vector<ButtonEvent>& out);
  void settled(size_t i, double t, std::vector<ButtonEvent>& out);

  std::vector<Button> buttons_;
  std::vector<Chord> chords_;
  double longPressS_ = 3.0;
  double chordWindowS_ = 0.15;
};

}  // namespace emboss
