// Evdev pen events to PenSamples: the state machine shared by evemu replay and the live evdev back end.
#include "input/evdev_pen_state.h"

#include <algorithm>

namespace emboss {

std::optional<std::string> evdevUnusableReason(const EvdevCaps& caps) {
  const auto x = caps.abs.find(evcode::kAbsX);
  const auto y = caps.abs.find(evcode::kAbsY);
  if (x == caps.abs.end() || y == caps.abs.end()) {
    return std::string("no absolute X/Y axes (a mouse, keyboard or button device, not a tablet)");
  }
  if (x->second.max <= x->second.min || y->second.max <= y->second.min) {
    return std::string("ABS_X/ABS_Y have an empty range (max <= min); the driver did not set the tablet size");
  }
  if (!caps.hasToolPen && (caps.hasToolFinger || caps.hasMultitouch)) {
    return std::string("a touchpad or touch screen (finger tool, no pen tool)");
  }
  const bool hasPressure = caps.abs.count(evcode::kAbsPressure) != 0;
  if (!caps.hasToolPen && !caps.hasStylus && !(hasPressure && caps.hasTouch)) {
    return std::string("absolute axes but nothing pen-like (no BTN_TOOL_PEN, BTN_STYLUS or pressure with BTN_TOUCH)");
  }
  return std::nullopt;
}

EvdevPenState::EvdevPenState(std::map<int, AbsRange> axes, bool hasToolKeys, bool hasTouchKey)
    : axes_(std::move(axes)), hasToolKeys_(hasToolKeys), hasTouchKey_(hasTouchKey) {}

double EvdevPenState::normalise(int32_t value, const AbsRange& r) {
  if (r.max <= r.min) return 0.0;
  const double v = (static_cast<double>(value) - r.min) / (static_cast<double>(r.max) - r.min);
  return std::clamp(v, 0.0, 1.0);
}

std::optional<PenSample> EvdevPenState::feed(double time_s, int type, int code, int32_t value) {
  if (type == evcode::kEvSyn) {
    if (code == evcode::kSynDropped) {
      dropping_ = true;
      return std::nullopt;
    }
    if (code != evcode::kSynReport) return std::nullopt;
    if (dropping_) {
      dropping_ = false;
      return std::nullopt;
    }
    PenSample s;
    s.time_s = time_s;
    const auto ax = axes_.find(evcode::kAbsX);
    const auto ay = axes_.find(evcode::kAbsY);
    const auto ap = axes_.find(evcode::kAbsPressure);
    s.x = ax != axes_.end() ? normalise(x_, ax->second) : 0.0;
    s.y = ay != axes_.end() ? normalise(y_, ay->second) : 0.0;
    s.tip = hasTouchKey_ ? touch_ : (ap != axes_.end() && pressure_ > ap->second.min);
    if (ap != axes_.end()) {
      s.pressure = normalise(pressure_, ap->second);
    } else {
      s.pressure = s.tip ? 1.0 : 0.0;
    }
    s.inRange = (hasToolKeys_ ? toolsDown_ != 0 : sawPosition_) || s.tip;
    s.barrel1 = stylus_;
    s.barrel2 = stylus2_;
    return s;
  }
  if (dropping_) return std::nullopt;
  if (type == evcode::kEvAbs) {
    switch (code) {
      case evcode::kAbsX: x_ = value; sawPosition_ = true; break;
      case evcode::kAbsY: y_ = value; sawPosition_ = true; break;
      case evcode::kAbsPressure: pressure_ = value; break;
      default: break;
    }
  } else if (type == evcode::kEvKey) {
    const bool down = value != 0;  // 2 (autorepeat) counts as down
    if (code >= evcode::kBtnToolPen && code <= evcode::kBtnToolAirbrush) {
      const unsigned bit = 1u << (code - evcode::kBtnToolPen);
      toolsDown_ = down ? (toolsDown_ | bit) : (toolsDown_ & ~bit);
      hasToolKeys_ = true;  // the device has them even if its description did not say so
      if (!down && toolsDown_ == 0) sawPosition_ = false;
    } else if (code == evcode::kBtnTouch) {
      touch_ = down;
      hasTouchKey_ = true;
    } else if (code == evcode::kBtnStylus) {
      stylus_ = down;
    } else if (code == evcode::kBtnStylus2) {
      stylus2_ = down;
    }
  }
  return std::nullopt;
}

}  // namespace emboss
