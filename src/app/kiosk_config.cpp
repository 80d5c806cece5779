// Reading the kiosk's key = value configuration, forgiving line by line.
#include "app/kiosk_config.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>

namespace emboss {

namespace {

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r");
  if (b == std::string::npos) return {};
  const auto e = s.find_last_not_of(" \t\r");
  return s.substr(b, e - b + 1);
}

bool toNumber(const std::string& s, double& out) {
  if (s.empty()) return false;
  char* end = nullptr;
  errno = 0;
  const double v = std::strtod(s.c_str(), &end);
  if (errno != 0 || end == s.c_str() || *end != '\0' || !std::isfinite(v)) return false;
  out = v;
  return true;
}

// The line without its comment: '#' starts one at the start of the line or after a blank, so a
// '#' inside a value (a path, a key name) stays part of it.
std::string stripComment(const std::string& line) {
  for (std::size_t i = 0; i < line.size(); ++i)
    if (line[i] == '#' && (i == 0 || line[i - 1] == ' ' || line[i - 1] == '\t')) return line.substr(0, i);
  return line;
}

// Where each key was last set (line numbers, 1-based); only for checkKioskConfig.
using KeyLines = std::map<std::string, std::vector<int>>;

}  // namespace

bool isCameraSpec(const std::string& s) {
  return s == "auto" || s == "none" || s.rfind("/dev/", 0) == 0 || (s.size() > 5 && s.rfind("file:", 0) == 0);
}

bool parseSizeWxH(const std::string& s, int& w, int& h) {
  int a = 0, b = 0;
  char tail = 0;
  if (std::sscanf(s.c_str(), "%dx%d%c", &a, &b, &tail) != 2) return false;
  if (a < 16 || b < 16 || a > 16384 || b > 16384) return false;
  w = a, h = b;
  return true;
}

std::map<std::string, Action> defaultKeyMap() {
  return {
      {"Right", Action::NextTool},   {"Tab", Action::NextTool},       {"Left", Action::PrevTool},
      {"Up", Action::SizeUp},        {"plus", Action::SizeUp},        {"equal", Action::SizeUp},
      {"KP_Add", Action::SizeUp},    {"WheelUp", Action::SizeUp},     {"Down", Action::SizeDown},
      {"minus", Action::SizeDown},   {"KP_Subtract", Action::SizeDown}, {"WheelDown", Action::SizeDown},
      {"m", Action::NextMetal},      {"z", Action::Undo},             {"BackSpace", Action::Undo},
      {"y", Action::Redo},           {"t", Action::Turn},             {"space", Action::Turn},
      {"n", Action::NewSheet},       {"Return", Action::NewSheet},    {"c", Action::Capture},
      {"F12", Action::Staff},
      {"Escape", Action::Quit},      {"q", Action::Quit},
  };
}

namespace {

KioskConfig parseLines(const std::string& text, const std::string& name, KioskConfig c,
                       std::vector<std::string>& warnings, KeyLines* keyLines) {
  std::istringstream in(text);
  std::string line;
  int lineNo = 0;
  auto warn = [&](const std::string& what) {
    warnings.push_back(name + ":" + std::to_string(lineNo) + ": " + what);
  };
  auto positive = [&](const std::string& key, const std::string& v, double& out) {
    double d;
    if (!toNumber(v, d) || !(d > 0)) return warn(key + " must be a positive number, not '" + v + "' (kept " + std::to_string(out) + ")");
    out = d;
  };
  while (std::getline(in, line)) {
    ++lineNo;
    line = trim(stripComment(line));
    if (line.empty()) continue;
    const auto eq = line.find('=');
    if (eq == std::string::npos) {
      warn("expected 'key = value', got '" + line + "'");
      continue;
    }
    const std::string key = trim(line.substr(0, eq)), v = trim(line.substr(eq + 1));
    if (keyLines) (*keyLines)[key].push_back(lineNo);
    if (key == "display") {
      if (v == "auto" || v == "kms" || v == "x11" || v == "headless" || v == "osmesa") c.display = v;
      else warn("display must be auto, kms, x11, headless or osmesa, not '" + v + "'");
    } else if (key == "size") {
      if (!parseSizeWxH(v, c.width, c.height)) warn("size must be WxH, e.g. 1280x800, not '" + v + "'");
    } else if (key == "tablet") {
      if (v == "auto" || v == "none" || v.rfind("evemu:", 0) == 0) c.tablet = v;
      else warn("tablet must be auto, none or evemu:PATH, not '" + v + "'");
    } else if (key == "buttons") {
      if (v.empty()) warn("buttons must be auto, none or the path of a buttons.json");
      else c.buttons = v;
    } else if (key == "camera") {
      if (isCameraSpec(v)) c.camera = v;
      else warn("camera must be auto, none, /dev/videoN or file:PNG, not '" + v + "'");
    } else if (key == "tablet_aspect") {
      positive(key, v, c.tabletAspect);
    } else if (key == "pieces_dir") {
      c.piecesDir = v;
    } else if (key == "sessions_dir") {
      c.sessionsDir = v;
    } else if (key == "export_dir") {
      c.exportDir = v;
    } else if (key == "take_home") {
      if (auto set = parseTakeHomeSet(v)) c.takeHome = *set;
      else warn("take_home: " + set.error());
    } else if (key == "retention_days") {
      positive(key, v, c.retentionDays);
    } else if (key == "retention_mb") {
      positive(key, v, c.retentionMb);
    } else if (key == "idle_seconds") {
      positive(key, v, c.idleSeconds);
    } else if (key == "countdown_seconds") {
      positive(key, v, c.countdownSeconds);
    } else if (key == "staff_idle_seconds") {
      positive(key, v, c.staffIdleSeconds);
    } else if (key == "staff_chord_seconds") {
      positive(key, v, c.staffChordSeconds);
    } else if (key == "staff_chord") {
      const auto plus = v.find('+');
      const Action a = plus == std::string::npos ? Action::None : actionFromName(trim(v.substr(0, plus)));
      const Action b = plus == std::string::npos ? Action::None : actionFromName(trim(v.substr(plus + 1)));
      if (a == Action::None || b == Action::None || a == b) warn("staff_chord must be two different actions, e.g. undo+redo, not '" + v + "'");
      else c.staffChord = {a, b};
    } else if (key == "metal") {
      if (v == "copper" || v == "brass" || v == "silver" || v == "aluminium") c.metal = v;
      else warn("metal must be copper, brass, silver or aluminium, not '" + v + "'");
    } else if (key == "sheet") {
      double w = 0, h = 0, t = 0;
      char tail = 0;
      if (std::sscanf(v.c_str(), "%lfx%lfx%lf%c", &w, &h, &t, &tail) == 3 && w >= 20 && h >= 20 && t > 0.05 && t < 5 &&
          w <= 600 && h <= 600)
        c.sheetWidth = w, c.sheetHeight = h, c.sheetThickness = t;
      else
        warn("sheet must be WxHxT in mm, e.g. 120x80x1, not '" + v + "'");
    } else if (key == "threads") {
      double d;
      if (toNumber(v, d) && d >= 0 && d <= 256 && d == std::floor(d)) c.threads = static_cast<int>(d);
      else warn("threads must be a whole number 0..256, not '" + v + "'");
    } else if (key == "attract_speed") {
      positive(key, v, c.attractSpeed);
    } else if (key == "pen_button1" || key == "pen_button2") {
      const Action a = actionFromName(v);
      if (a == Action::None && v != "none") warn("unknown action '" + v + "' for " + key);
      else (key == "pen_button1" ? c.penButton1 : c.penButton2) = a;
    } else if (key.rfind("key.", 0) == 0 && key.size() > 4) {
      const Action a = actionFromName(v);
      if (a == Action::None && v != "none") warn("unknown action '" + v + "' for " + key);
      else c.keys[key.substr(4)] = a;
    } else {
      warn("unknown key '" + key + "' (ignored)");
    }
  }
  return c;
}

}  // namespace

KioskConfig parseKioskConfig(const std::string& text, const std::string& name, KioskConfig c,
                             std::vector<std::string>& warnings) {
  return parseLines(text, name, std::move(c), warnings, nullptr);
}

std::vector<std::string> checkKioskConfig(const std::string& text, const std::string& name) {
  std::vector<std::string> problems;
  KeyLines lines;
  const KioskConfig c = parseLines(text, name, KioskConfig{}, problems, &lines);
  auto at = [&](const std::string& key) { return name + ":" + std::to_string(lines[key].back()) + ": "; };
  for (const auto& [key, seen] : lines)
    for (std::size_t i = 1; i < seen.size(); ++i)
      problems.push_back(name + ":" + std::to_string(seen[i]) + ": " + key + " is set again (first on line " +
                         std::to_string(seen[0]) + "); the last one wins");
  // Paths the kiosk would only find missing at run time (and then go on without).
  auto mustExist = [&](const std::string& key, const std::filesystem::path& path, const char* what) {
    std::error_code ec;
    if (lines.count(key) && !std::filesystem::exists(path, ec))
      problems.push_back(at(key) + key + ": " + what + " " + path.string() + " does not exist");
  };
  if (c.buttons != "auto" && c.buttons != "none") mustExist("buttons", c.buttons, "the buttons file");
  if (c.tablet.rfind("evemu:", 0) == 0) mustExist("tablet", c.tablet.substr(6), "the recording");
  if (c.camera.rfind("file:", 0) == 0) mustExist("camera", c.camera.substr(5), "the picture");
  if (!c.piecesDir.empty()) mustExist("pieces_dir", c.piecesDir, "the folder");
  std::stable_sort(problems.begin(), problems.end(), [&](const std::string& a, const std::string& b) {
    auto lineOf = [&](const std::string& p) { return std::atoi(p.c_str() + name.size() + 1); };
    return lineOf(a) < lineOf(b);
  });
  return problems;
}

std::vector<std::string> checkKioskConfigFile(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return {path.string() + ": cannot read the config (" + std::strerror(errno) + ")"};
  std::stringstream ss;
  ss << in.rdbuf();
  return checkKioskConfig(ss.str(), path.string());
}

KioskConfig loadKioskConfig(const std::filesystem::path& path, KioskConfig base, std::vector<std::string>& warnings) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    warnings.push_back(path.string() + ": cannot read the config (" + std::strerror(errno) + "); using the defaults");
    return base;
  }
  std::stringstream ss;
  ss << in.rdbuf();
  return parseKioskConfig(ss.str(), path.string(), std::move(base), warnings);
}

}  // namespace emboss
