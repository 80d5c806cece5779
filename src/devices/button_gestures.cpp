// Debounce, long press and chords as a small state machine per button, driven by explicit times.
#include "devices/button_gestures.h"

#include <algorithm>
#include <limits>

namespace emboss {

namespace {
constexpr double kNever = std::numeric_limits<double>::infinity();
}  // namespace

ButtonGestures::ButtonGestures(const ButtonConfig& config)
    : longPressS_(config.longPressS), chordWindowS_(config.chordWindowS) {
  for (const auto& line : config.buttons) {
    Button b;
    b.action = line.action;
    b.longPress = line.longPress;
    b.debounceS = std::max(0.0, line.debounceS);
    buttons_.push_back(b);
  }
  for (const auto& c : config.chords) {
    const int a = config.buttonFor(c.buttons[0]);
    const int b = config.buttonFor(c.buttons[1]);
    if (a < 0 || b < 0 || a == b) continue;  // parseButtonConfig rejects these; stay safe for hand-made configs
    if (buttons_[a].chord >= 0 || buttons_[b].chord >= 0) continue;
    Chord chord;
    chord.action = c.action;
    chord.holdS = std::max(0.0, c.holdS);
    chord.a = static_cast<size_t>(a);
    chord.b = static_cast<size_t>(b);
    buttons_[a].chord = buttons_[b].chord = static_cast<int>(chords_.size());
    chords_.push_back(chord);
  }
}

void ButtonGestures::reset(size_t button, bool pressed, double t) {
  Button& b = buttons_[button];
  b.raw = b.stable = pressed;
  b.rawT = t;
  b.phase = pressed ? Phase::Ignored : Phase::Idle;
}

void ButtonGestures::edge(size_t button, bool pressed, double t, std::vector<ButtonEvent>& out) {
  advance(t, out);
  Button& b = buttons_[button];
  b.raw = pressed;
  b.rawT = t;
  advance(t, out);  // a zero debounce settles at once
}

void ButtonGestures::advance(double t, std::vector<ButtonEvent>& out) {
  for (;;) {
    size_t which = 0;
    const auto d = deadline(&which);
    if (!d || *d > t) return;
    fire(which, *d, out);
  }
}

std::optional<double> ButtonGestures::nextDeadline() const {
  size_t which = 0;
  return deadline(&which);
}

double ButtonGestures::buttonDeadline(const Button& b) const {
  double d = b.raw != b.stable ? b.rawT + b.debounceS : kNever;
  if (b.phase == Phase::Pending) {
    if (b.longPress != Action::None) {
      d = std::min(d, b.pressT + longPressS_);
    } else if (b.chord >= 0) {
      // The window lapses once a partner pressed within it would have settled too.
      const Chord& c = chords_[b.chord];
      const double settle = std::max(buttons_[c.a].debounceS, buttons_[c.b].debounceS);
      d = std::min(d, b.pressT + chordWindowS_ + settle);
    }
  }
  return d;
}

std::optional<double> ButtonGestures::deadline(size_t* which) const {
  double best = kNever;
  for (size_t i = 0; i < buttons_.size(); ++i) {
    const double d = buttonDeadline(buttons_[i]);
    if (d < best) best = d, *which = i;
  }
  for (size_t i = 0; i < chords_.size(); ++i) {
    const Chord& c = chords_[i];
    if (c.active && !c.fired && c.startT + c.holdS < best) best = c.startT + c.holdS, *which = buttons_.size() + i;
  }
  if (best == kNever) return std::nullopt;
  return best;
}

void ButtonGestures::fire(size_t which, double t, std::vector<ButtonEvent>& out) {
  if (which >= buttons_.size()) {
    Chord& c = chords_[which - buttons_.size()];
    out.push_back({t, c.action, true, false});
    c.fired = true;
    return;
  }
  Button& b = buttons_[which];
  const double settle = b.raw != b.stable ? b.rawT + b.debounceS : kNever;
  if (settle <= t) {
    b.stable = b.raw;
    settled(which, b.rawT, out);
    return;
  }
  // A pending press: held long enough, or its chord window lapsed alone.
  if (b.longPress != Action::None) {
    out.push_back({b.pressT + longPressS_, b.longPress, true, true});
    b.phase = Phase::Held;
  } else {
    out.push_back({b.pressT, b.action, true, false});
    b.phase = Phase::Pressed;
  }
}

void ButtonGestures::settled(size_t i, double t, std::vector<ButtonEvent>& out) {
  Button& b = buttons_[i];
  if (b.stable) {
    if (b.phase == Phase::Ignored) return;
    if (b.chord >= 0) {
      Chord& c = chords_[b.chord];
      Button& partner = buttons_[c.a == i ? c.b : c.a];
      if (!c.active && partner.phase == Phase::Pending && t - partner.pressT <= chordWindowS_) {
        c.active = true;
        c.fired = false;
        c.startT = t;
        b.phase = partner.phase = Phase::Chord;
        if (c.holdS <= 0.0) {
          out.push_back({t, c.action, true, false});
          c.fired = true;
        }
        return;
      }
    }
    if (b.longPress != Action::None || b.chord >= 0) {
      b.phase = Phase::Pending;
      b.pressT = t;
      return;
    }
    out.push_back({t, b.action, true, false});
    b.phase = Phase::Pressed;
    return;
  }

  switch (b.phase) {
    case Phase::Pending:  // a tap: its own action, late but with its true press time
      out.push_back({b.pressT, b.action, true, false});
      out.push_back({t, b.action, false, false});
      break;
    case Phase::Pressed:
      out.push_back({t, b.action, false, false});
      break;
    case Phase::Held:
      out.push_back({t, b.longPress, false, true});
      break;
    case Phase::Chord: {
      Chord& c = chords_[b.chord];
      if (c.fired) out.push_back({t, c.action, false, false});
      c.active = c.fired = false;
      Button& partner = buttons_[c.a == i ? c.b : c.a];
      if (partner.phase == Phase::Chord) partner.phase = Phase::Ignored;  // its release does nothing
      break;
    }
    case Phase::Idle:
    case Phase::Ignored:
      break;
  }
  b.phase = Phase::Idle;
}

}  // namespace emboss
