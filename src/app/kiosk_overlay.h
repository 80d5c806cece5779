// What the kiosk draws over the metal: big pictograms for tool, size and metal, the pressure bar,
// the pen's footprint, the "still there?" countdown, the attract hint and the staff screen.
#pragma once

#include <string>
#include <vector>

#include "app/kiosk_states.h"
#include "app/surface_pick.h"
#include "devices/display.h"

namespace emboss {

class Workbench;

struct StaffView {
  std::vector<std::string> menu;
  size_t selected = 0;
  std::vector<std::string> lines;  // diagnostics, one per line
  std::string message;             // the last staff action's outcome
  bool messageIsError = false;
};

struct OverlayState {
  KioskMode mode = KioskMode::Attract;
  double now = 0;  // seconds, for the pulses
  int width = 1280, height = 800;
  const Workbench* bench = nullptr;  // visitor and still-there
  std::string title;                 // attract: the piece
  double progress = 0;               // attract: 0..1
  double countdownLeft = 0, countdownTotal = 1;
  StaffView staff;
  // Capture drawing (visitor and still-there): a still being taken and traced, the traced lines on
  // offer (screen pixels, projected onto the plate), the last outcome.
  bool capturing = false;
  bool captureOffered = false;
  std::vector<std::vector<std::pair<double, double>>> guide;
  std::string captureMessage;
  bool captureMessageIsError = false;
};

// Nothing here must be read to start: the pictograms say tool, size and metal, the bar says
// pressure, the pulsing ring says "touch". Text only names things for those who read.
Overlay buildOverlay(const OverlayState& s);

// Where the staff menu's items are (pixels), for tapping them with the pen.
std::vector<ScreenBox> staffMenuBoxes(int width, int height, size_t count);

}  // namespace emboss
