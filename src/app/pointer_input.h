// The mouse and keyboard standing in for the pen and the buttons (a window on a desktop).
#pragma once

#include <deque>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "devices/buttons.h"
#include "devices/pen.h"

namespace emboss {

// One event of a window, in window pixels (origin top left). The platform's window back end
// (display_x11) is translated into these by the kiosk's main(), so this stays free of X11.
struct PointerEvent {
  enum class Type { Move, Down, Up, Key, Leave };
  Type type = Type::Move;
  double x = 0, y = 0;
  std::string key;  // Key: the key's name ("Right", "z", "WheelUp", ...)
};

// The mouse as a pen: the left button is the tip; the window is the tablet (samples are the
// pointer's position over the window, 0..1, so the kiosk maps them 1:1 onto the screen). A mouse
// has no pressure: the stand-in is a steady, medium press (0.6) that rises from 0.45 over the first
// 150 ms of a press, as a pen's does when it lands; the keys [ and ] make it lighter or firmer.
class MousePen final : public PenSource {
 public:
  using Clock = std::function<double()>;
  MousePen(int width, int height, Clock now);
  void feed(const PointerEvent& e);
  std::string name() const override { return "mouse (left button = pen tip)"; }
  bool poll(std::vector<PenSample>& out) override;
  double level() const { return level_; }

 private:
  double pressureAt(double t) const;
  int w_, h_;
  Clock now_;
  bool down_ = false, inside_ = false;
  double x_ = 0, y_ = 0, downAt_ = 0;
  double level_ = 0.6;
  std::vector<PenSample> out_;
};

// The keyboard as the buttons: each key press is a press and a release of the mapped action.
class KeyButtons final : public ButtonSource {
 public:
  using Clock = std::function<double()>;
  KeyButtons(std::map<std::string, Action> keys, Clock now);
  void feed(const PointerEvent& e);
  std::string name() const override { return "keyboard"; }
  bool poll(std::vector<ButtonEvent>& out) override;

 private:
  std::map<std::string, Action> keys_;
  Clock now_;
  std::vector<ButtonEvent> out_;
};

}  // namespace emboss
