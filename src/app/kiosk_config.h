// The kiosk's configuration: a `key = value` file (firmware-app/kiosk.conf), then command-line overrides.
#pragma once

#include <filesystem>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "devices/buttons.h"
#include "export/take_home.h"

namespace emboss {

// The keyboard's stand-in for the kiosk's buttons (X11 keysym names, as display_x11.h gives them).
std::map<std::string, Action> defaultKeyMap();

struct KioskConfig {
  std::string display = "auto";  // auto | kms | x11 | headless | osmesa
  int width = 1280, height = 800;  // the window or headless picture (kms takes the screen's mode)
  std::string tablet = "auto";   // auto | evemu:PATH | none
  std::string buttons = "auto";  // auto (GPIO with the built-in wiring) | none | PATH of a buttons.json
  std::string camera = "auto";   // auto (the first V4L2 camera) | /dev/videoN | file:PNG | none: capture drawing
  double tabletAspect = 1.6;     // width / height of the tablet's active area (Intuos 6x9: 1.6)
  std::filesystem::path piecesDir;                                  // empty: searched (see docs/kiosk.md)
  std::filesystem::path sessionsDir;  // empty: $STATE_DIRECTORY/sessions, else ~/.local/state/emboss-kiosk/sessions
  std::filesystem::path exportDir = "/media/emboss-export";         // staff export target (a USB stick)
  TakeHomeSet takeHome;  // take_home: files the staff export adds beside each session (default none)
  bool exportAnyDir = false;  // the staff menu may export to a folder on the kiosk's own disk (tests only)
  double retentionDays = 365;     // finished sessions older than this are deleted (oldest first)
  double retentionMb = 4096;      // ... and beyond this much space, oldest first (a year on a 16 GB card)
  double idleSeconds = 60;        // a visitor who does nothing this long is asked "still there?"
  double countdownSeconds = 15;   // ... and this long later the session is saved and attract resumes
  double staffIdleSeconds = 300;  // staff mode closes itself after this long untouched
  double staffChordSeconds = 3;   // hold the chord this long to enter staff mode
  std::pair<Action, Action> staffChord{Action::Undo, Action::Redo};
  std::string metal = "copper";   // the metal of a fresh sheet
  double sheetWidth = 120, sheetHeight = 80, sheetThickness = 1.0;  // mm
  int threads = 0;                // render threads (0: one per core)
  double attractSpeed = 1.0;      // > 1 replays the pieces faster
  Action penButton1 = Action::NextTool;  // the pen's barrel buttons (BTN_STYLUS, BTN_STYLUS2)
  Action penButton2 = Action::Undo;
  std::map<std::string, Action> keys = defaultKeyMap();  // X11 key name -> action; key.NAME = ACTION adds
};

// Parses a config file's text over `base`. A bad line never stops the kiosk: it is skipped and a
// warning naming the line is appended to `warnings`, and the value keeps its default.
KioskConfig parseKioskConfig(const std::string& text, const std::string& name, KioskConfig base,
                             std::vector<std::string>& warnings);
// Reads a file; a missing or unreadable file is one warning and `base` unchanged.
KioskConfig loadKioskConfig(const std::filesystem::path& path, KioskConfig base, std::vector<std::string>& warnings);

// The strict reading `emboss-kiosk --check-config` does: every line parseKioskConfig would warn
// about, a key set twice, and a file or folder the config names that does not exist (buttons,
// an evemu: recording, a file: camera still, pieces_dir). Each problem is "NAME:LINE: message";
// none means the config is good.
std::vector<std::string> checkKioskConfig(const std::string& text, const std::string& name);
// The same for a file; an unreadable file is one problem.
std::vector<std::string> checkKioskConfigFile(const std::filesystem::path& path);

// "1280x800" -> 1280, 800 (each 16..16384). False when malformed.
bool parseSizeWxH(const std::string& s, int& w, int& h);
// Whether s names a camera as the `camera` key and --camera take it: auto, none, /dev/videoN or
// file:PNG.
bool isCameraSpec(const std::string& s);

}  // namespace emboss
