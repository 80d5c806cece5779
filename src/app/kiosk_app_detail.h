// What the kiosk app's source files (kiosk_app, kiosk_input, kiosk_staff, kiosk_capture) share:
// the staff menu, timings and text helpers. Internal to src/app.
#pragma once

#include <cstddef>
#include <cstdio>
#include <string>
#include <vector>

namespace emboss::kiosk_detail {

inline const char* const kStaffMenu[] = {"Back to the exhibit", "Export sessions", "Reset the exhibit", "Capture a drawing"};
inline constexpr size_t kStaffItems = 4;
inline constexpr double kCameraCheckSeconds = 2.0;  // how often an idle camera is asked whether it is still there
inline constexpr double kCaptureNoteSeconds = 8.0;  // how long a capture's outcome stays on the screen
inline constexpr size_t kStaffLineChars = 56;       // what fits beside the staff menu at 1280x800

// Splits text at spaces into lines of at most n characters (a longer word is cut).
std::vector<std::string> wrapWords(const std::string& text, size_t n);

// printf of one number.
inline std::string fmt(const char* f, double a) {
  char buf[128];
  std::snprintf(buf, sizeof buf, f, a);
  return buf;
}

}  // namespace emboss::kiosk_detail
