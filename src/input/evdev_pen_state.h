// Evdev pen events to PenSamples: the state machine shared by evemu replay and the live evdev back end.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <string>

#include "devices/pen.h"

namespace emboss {

// The Linux input codes this code needs (linux/input-event-codes.h), spelt out so that src/ stays
// free of OS headers.
namespace evcode {
inline constexpr int kEvSyn = 0x00;
inline constexpr int kEvKey = 0x01;
inline constexpr int kEvAbs = 0x03;
inline constexpr int kSynReport = 0x00;
inline constexpr int kSynDropped = 0x03;
inline constexpr int kAbsX = 0x00;
inline constexpr int kAbsY = 0x01;
inline constexpr int kAbsPressure = 0x18;
inline constexpr int kAbsDistance = 0x19;
inline constexpr int kAbsMtPositionX = 0x35;
inline constexpr int kBtnToolPen = 0x140;
inline constexpr int kBtnToolRubber = 0x141;
inline constexpr int kBtnToolBrush = 0x142;
inline constexpr int kBtnToolPencil = 0x143;
inline constexpr int kBtnToolAirbrush = 0x144;
inline constexpr int kBtnToolFinger = 0x145;
inline constexpr int kBtnToolMouse = 0x146;
inline constexpr int kBtnTouch = 0x14a;
inline constexpr int kBtnStylus = 0x14b;
inline constexpr int kBtnStylus2 = 0x14c;
inline constexpr int kBtnStylus3 = 0x149;
inline constexpr int kPropPointer = 0x00;
inline constexpr int kPropDirect = 0x01;
}  // namespace evcode

// One absolute axis as the kernel describes it (struct input_absinfo).
struct AbsRange {
  int32_t min = 0;
  int32_t max = 0;
  int32_t fuzz = 0;
  int32_t flat = 0;
  int32_t resolution = 0;
};

// What a device can report, enough to tell a pen tablet from a mouse, a touchpad or a keyboard.
struct EvdevCaps {
  std::string name;
  uint16_t vendorId = 0;
  uint16_t productId = 0;
  std::map<int, AbsRange> abs;  // by ABS_* code
  bool hasToolPen = false;      // BTN_TOOL_PEN (or another pen tool: rubber, brush, pencil, airbrush)
  bool hasTouch = false;        // BTN_TOUCH
  bool hasStylus = false;       // BTN_STYLUS
  bool hasToolFinger = false;   // BTN_TOOL_FINGER (touchpads, touch screens)
  bool hasMultitouch = false;   // ABS_MT_POSITION_X
  bool propDirect = false;      // INPUT_PROP_DIRECT (screen tablets and touch screens)
};

// Why a device cannot serve as the pen, or nullopt when it can. A pen needs ABS_X and ABS_Y with a
// usable range, and something pen-like: BTN_TOOL_PEN, or BTN_STYLUS, or ABS_PRESSURE with
// BTN_TOUCH and no finger tool.
std::optional<std::string> evdevUnusableReason(const EvdevCaps& caps);

// Feeds evdev events and emits a PenSample at each SYN_REPORT.
//  - x, y: (value - min) / (max - min) of the device's ABS_X/ABS_Y ranges, clamped to 0..1;
//  - pressure: the same with ABS_PRESSURE; without a pressure axis, 1 while the tip touches;
//  - tip: BTN_TOUCH; on a device without BTN_TOUCH, pressure above its minimum;
//  - inRange: a pen tool key (BTN_TOOL_PEN and friends) when the device has them; a device without
//    tool keys only reports while the pen is near, so there inRange becomes true with the first
//    position and stays so; the tip touching always implies inRange;
//  - barrel1/barrel2: BTN_STYLUS/BTN_STYLUS2.
// After SYN_DROPPED, events are discarded up to the next SYN_REPORT (the kernel's rule).
class EvdevPenState {
 public:
  EvdevPenState() = default;
  // hasToolKeys: whether the device reports BTN_TOOL_* proximity; hasTouchKey: whether it reports
  // BTN_TOUCH (both from its capabilities). Without BTN_TOUCH the tip is pressure above its minimum.
  EvdevPenState(std::map<int, AbsRange> axes, bool hasToolKeys, bool hasTouchKey);

  // Returns a sample when the event is a SYN_REPORT closing a frame.
  std::optional<PenSample> feed(double time_s, int type, int code, int32_t value);

  bool hasAxis(int code) const { return axes_.count(code) != 0; }

 private:
  static double normalise(int32_t value, const AbsRange& r);

  std::map<int, AbsRange> axes_;
  bool hasToolKeys_ = false;
  bool dropping_ = false;
  bool sawPosition_ = false;
  bool hasTouchKey_ = false;
  int32_t x_ = 0;
  int32_t y_ = 0;
  int32_t pressure_ = 0;
  unsigned toolsDown_ = 0;  // bit per pen tool key
  bool touch_ = false;
  bool stylus_ = false;
  bool stylus2_ = false;
};

}  // namespace emboss
