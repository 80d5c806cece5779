// The X11 display: GLES through EGL in a fixed-size window titled "emboss", for development on a
// desktop (or Xvfb); its mouse and keyboard stand in for the pen and the buttons.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "devices/display.h"
#include "gl/gl_presenter.h"
#include "util/result.h"

namespace emboss {

// One input event from the window. Coordinates are window pixels, origin top left, the same
// space as the frame and the overlay.
struct X11Event {
  enum class Type {
    kMove,     // the pointer moved (with or without the left button held)
    kPenDown,  // left button pressed: the pen tip touches
    kPenUp,    // left button released
    kKey,      // a key was pressed; `key` names it
    kClose,    // the window manager asked to close the window
  };
  Type type = Type::kMove;
  float x = 0, y = 0;
  bool penDown = false;    // left button held after this event
  std::string key;         // kKey: X keysym name: "a", "A", "1", "space", "Return", "Escape", "F1",
                           // "Left", "plus", "minus"; the wheel gives "WheelUp" and "WheelDown"
  std::uint32_t timeMs = 0;  // X server time
};

// The latest pointer state, for polling without events.
struct X11Input {
  float x = 0, y = 0;
  bool penDown = false;
  bool inside = false;  // the pointer is in the window
};

class X11Display : public Display {
 public:
  // Appends the window's pending events to `out` without blocking. Returns false once the window
  // was closed or the X connection is gone (the events before that are still appended).
  virtual bool pollX11Events(std::vector<X11Event>& out) = 0;
  virtual X11Input input() const = 0;
  // The X window id (for tests and tools that send it events).
  virtual unsigned long windowId() const = 0;
};

// The X11 display of a Display made by createX11Display() or createDisplay("x11"/"auto"), or null.
inline X11Display* asX11Display(Display* display) { return dynamic_cast<X11Display*>(display); }

// A width x height window on $DISPLAY. Fails with "x11: $DISPLAY not set (...)" or "x11: cannot
// open display ':1' (...)" when there is no X server. name() is e.g. "x11 (EGL window 1280x800,
// llvmpipe)". present() swaps with vsync and returns false once the window is closed or the
// server is gone.
Result<std::unique_ptr<Display>> createX11Display(int width, int height, const GlPresenterSettings& settings = {});

}  // namespace emboss
