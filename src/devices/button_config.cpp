// Reading and checking the button configuration (JSON), with messages that say what to fix.
#include "devices/button_config.h"

#include <fstream>
#include <initializer_list>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>

namespace emboss {

namespace {

using nlohmann::json;

constexpr std::array<std::pair<LineBias, const char*>, 4> kBiasNames = {{
    {LineBias::AsIs, "as_is"},
    {LineBias::Disable, "disable"},
    {LineBias::PullUp, "pull_up"},
    {LineBias::PullDown, "pull_down"},
}};

// The actions a kiosk button may have (not none; quit is for the keyboard in development).
std::string knownActions() {
  std::string s;
  for (Action a : {Action::NextTool, Action::PrevTool, Action::SizeUp, Action::SizeDown, Action::NextMetal, Action::Undo,
                   Action::Redo, Action::Turn, Action::NewSheet, Action::Capture, Action::Staff}) {
    s += (s.empty() ? "" : ", ") + std::string(actionName(a));
  }
  return s;
}

// Typed access to one JSON object, every message prefixed with where it is ("buttons[2].line").
class Fields {
 public:
  Fields(const json& j, std::string where, std::string& error) : j_(j), where_(std::move(where)), error_(error) {}

  bool failed() const { return !error_.empty(); }
  std::string at(const char* key) const { return where_.empty() ? key : where_ + "." + key; }
  void setError(const std::string& message) {
    if (error_.empty()) error_ = message;
  }

  // Unknown keys are errors: a misspelt "activelow" must not be silently ignored.
  void onlyKeys(std::initializer_list<const char*> keys) {
    for (auto it = j_.begin(); it != j_.end(); ++it) {
      bool known = false;
      for (const char* k : keys) known = known || it.key() == k;
      if (known) continue;
      std::string list;
      for (const char* k : keys) list += (list.empty() ? "" : ", ") + std::string(k);
      setError((where_.empty() ? std::string() : where_ + ": ") + "unknown key '" + it.key() + "' (known: " + list + ")");
      return;
    }
  }

  std::optional<double> number(const char* key, double lo, double hi, const char* unit) {
    if (!j_.contains(key)) return std::nullopt;
    const json& v = j_[key];
    if (!v.is_number()) {
      setError(at(key) + ": expected a number of " + unit + ", got " + v.dump());
      return std::nullopt;
    }
    const double d = v.get<double>();
    if (!(d >= lo && d <= hi)) {
      std::ostringstream s;
      s << at(key) << ": " << v.dump() << " is out of range " << lo << ".." << hi << " " << unit;
      setError(s.str());
      return std::nullopt;
    }
    return d;
  }

  std::optional<unsigned> lineOffset(const char* key) {
    if (!j_.contains(key)) {
      setError(at(key) + ": missing; give the line offset on the chip (on a Raspberry Pi the BCM number, e.g. 17)");
      return std::nullopt;
    }
    const json& v = j_[key];
    if (!v.is_number_integer() || v.get<long long>() < 0 || v.get<long long>() > 65535) {
      setError(at(key) + ": expected a line offset, a whole number 0..65535, got " + v.dump());
      return std::nullopt;
    }
    return static_cast<unsigned>(v.get<long long>());
  }

  std::optional<bool> boolean(const char* key) {
    if (!j_.contains(key)) return std::nullopt;
    if (!j_[key].is_boolean()) {
      setError(at(key) + ": expected true or false, got " + j_[key].dump());
      return std::nullopt;
    }
    return j_[key].get<bool>();
  }

  std::optional<std::string> text(const char* key) {
    if (!j_.contains(key)) return std::nullopt;
    if (!j_[key].is_string() || j_[key].get<std::string>().empty()) {
      setError(at(key) + ": expected a non-empty string, got " + j_[key].dump());
      return std::nullopt;
    }
    return j_[key].get<std::string>();
  }

  std::optional<Action> action(const char* key, bool required) {
    if (!j_.contains(key)) {
      if (required) setError(at(key) + ": missing; one of " + knownActions());
      return std::nullopt;
    }
    return actionValue(j_[key], at(key));
  }

  std::optional<Action> actionValue(const json& v, const std::string& where) {
    if (!v.is_string()) {
      setError(where + ": expected an action name, one of " + knownActions() + "; got " + v.dump());
      return std::nullopt;
    }
    const std::string name = v.get<std::string>();
    const Action a = actionFromName(name);
    if (a == Action::Quit) {
      setError(where + ": 'quit' is for the keyboard during development, not a kiosk button");
      return std::nullopt;
    }
    if (a == Action::None) {
      setError(where + ": unknown action '" + name + "' (known: " + knownActions() + ")");
      return std::nullopt;
    }
    return a;
  }

  std::optional<GpioRead> read(const char* key) {
    if (!j_.contains(key)) return std::nullopt;
    const json& v = j_[key];
    if (v.is_string()) {
      for (GpioRead r : {GpioRead::Auto, GpioRead::Edges, GpioRead::Levels})
        if (v.get<std::string>() == gpioReadName(r)) return r;
    }
    setError(at(key) + ": " + v.dump() + " is not one of \"auto\", \"edges\", \"levels\"");
    return std::nullopt;
  }

  std::optional<LineBias> bias(const char* key) {
    if (!j_.contains(key)) return std::nullopt;
    const json& v = j_[key];
    if (v.is_string()) {
      for (const auto& [b, name] : kBiasNames)
        if (v.get<std::string>() == name) return b;
    }
    setError(at(key) + ": " + v.dump() + " is not one of \"as_is\", \"disable\", \"pull_up\", \"pull_down\"");
    return std::nullopt;
  }

 private:
  const json& j_;
  std::string where_;
  std::string& error_;
};

}  // namespace

const char* lineBiasName(LineBias b) {
  for (const auto& [bias, name] : kBiasNames)
    if (bias == b) return name;
  return "as_is";
}

const char* gpioReadName(GpioRead r) {
  switch (r) {
    case GpioRead::Auto: return "auto";
    case GpioRead::Edges: return "edges";
    case GpioRead::Levels: return "levels";
  }
  return "auto";
}

int ButtonConfig::buttonFor(Action a) const {
  for (size_t i = 0; i < buttons.size(); ++i)
    if (buttons[i].action == a) return static_cast<int>(i);
  return -1;
}

Result<ButtonConfig> parseButtonConfig(const std::string& text, const std::string& name) {
  json root;
  try {
    root = json::parse(text);
  } catch (const json::exception& e) {  // parse_error, and out_of_range for a number like 1e999
    return fail(name + ": not valid JSON: " + e.what());
  }
  if (!root.is_object()) return fail(name + ": expected a JSON object {\"buttons\": [...]} at the top");

  std::string error;
  ButtonConfig config;
  config.source = name;
  Fields top(root, "", error);
  top.onlyKeys({"chip", "active_low", "bias", "debounce_ms", "long_press_ms", "chord_window_ms", "read", "buttons", "chords"});

  // Top-level defaults for every button.
  ButtonLineConfig defaults;
  if (auto v = top.text("chip")) defaults.chip = *v;
  if (auto v = top.boolean("active_low")) defaults.activeLow = *v;
  if (auto v = top.bias("bias")) defaults.bias = *v;
  if (auto v = top.number("debounce_ms", 0, 1000, "ms")) defaults.debounceS = *v / 1000.0;
  if (auto v = top.number("long_press_ms", 500, 60000, "ms")) config.longPressS = *v / 1000.0;
  if (auto v = top.number("chord_window_ms", 10, 2000, "ms")) config.chordWindowS = *v / 1000.0;
  if (auto v = top.read("read")) config.read = *v;
  if (!error.empty()) return fail(name + ": " + error);

  if (!root.contains("buttons") || !root["buttons"].is_array() || root["buttons"].empty())
    return fail(name + ": \"buttons\" must be a non-empty array of {\"line\": N, \"action\": \"...\"}");
  const json& buttons = root["buttons"];
  for (size_t i = 0; i < buttons.size(); ++i) {
    const std::string where = "buttons[" + std::to_string(i) + "]";
    if (!buttons[i].is_object()) return fail(name + ": " + where + ": expected an object {\"line\": N, \"action\": \"...\"}");
    Fields f(buttons[i], where, error);
    f.onlyKeys({"line", "action", "chip", "active_low", "bias", "debounce_ms", "long_press"});
    ButtonLineConfig b = defaults;
    if (auto v = f.lineOffset("line")) b.line = *v;
    if (auto v = f.action("action", true)) b.action = *v;
    if (auto v = f.text("chip")) b.chip = *v;
    if (auto v = f.boolean("active_low")) b.activeLow = *v;
    if (auto v = f.bias("bias")) b.bias = *v;
    if (auto v = f.number("debounce_ms", 0, 1000, "ms")) b.debounceS = *v / 1000.0;
    if (auto v = f.action("long_press", false)) b.longPress = *v;
    if (!error.empty()) return fail(name + ": " + error);
    for (size_t k = 0; k < config.buttons.size(); ++k) {
      const auto& o = config.buttons[k];
      if (o.chip == b.chip && o.line == b.line)
        return fail(name + ": " + where + ": " + b.chip + " line " + std::to_string(b.line) + " is already buttons[" +
                    std::to_string(k) + "] (" + actionName(o.action) + "); one line, one button");
    }
    config.buttons.push_back(b);
  }

  if (root.contains("chords")) {
    const json& chords = root["chords"];
    if (!chords.is_array()) return fail(name + ": \"chords\" must be an array of {\"buttons\": [\"a\", \"b\"], \"action\": \"staff\"}");
    std::vector<int> inChord(config.buttons.size(), -1);
    for (size_t i = 0; i < chords.size(); ++i) {
      const std::string where = "chords[" + std::to_string(i) + "]";
      if (!chords[i].is_object()) return fail(name + ": " + where + ": expected an object {\"buttons\": [\"a\", \"b\"], \"action\": \"staff\"}");
      Fields f(chords[i], where, error);
      f.onlyKeys({"buttons", "action", "hold_ms"});
      ChordConfig c;
      if (auto v = f.action("action", false)) c.action = *v;
      if (auto v = f.number("hold_ms", 0, 60000, "ms")) c.holdS = *v / 1000.0;
      if (!error.empty()) return fail(name + ": " + error);
      const json& members = chords[i].contains("buttons") ? chords[i]["buttons"] : json();
      if (!members.is_array() || members.size() != 2)
        return fail(name + ": " + where + ".buttons: expected the actions of two buttons, e.g. [\"undo\", \"redo\"]");
      for (size_t m = 0; m < 2; ++m) {
        const std::string mw = where + ".buttons[" + std::to_string(m) + "]";
        auto a = f.actionValue(members[m], mw);
        if (!a) return fail(name + ": " + error);
        c.buttons[m] = *a;
        int found = -1, count = 0;
        for (size_t k = 0; k < config.buttons.size(); ++k)
          if (config.buttons[k].action == *a) found = static_cast<int>(k), ++count;
        if (count == 0) return fail(name + ": " + mw + ": no button has the action '" + actionName(*a) + "'");
        if (count > 1) return fail(name + ": " + mw + ": several buttons have the action '" + actionName(*a) + "'; a chord needs exactly one");
        if (inChord[found] >= 0)
          return fail(name + ": " + mw + ": the '" + actionName(*a) + "' button is already in chords[" + std::to_string(inChord[found]) +
                      "]; a button can be in one chord");
        inChord[found] = static_cast<int>(i);
      }
      if (c.buttons[0] == c.buttons[1]) return fail(name + ": " + where + ".buttons: a chord needs two different buttons");
      config.chords.push_back(c);
    }
  }
  return config;
}

Result<ButtonConfig> loadButtonConfig(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return fail(path.string() + ": cannot read the button configuration (missing, or no permission)");
  std::ostringstream ss;
  ss << in.rdbuf();
  return parseButtonConfig(ss.str(), path.string());
}

ButtonConfig defaultButtonConfig() {
  ButtonConfig c;
  c.source = "built-in (Raspberry Pi header, docs/hardware.md)";
  const std::pair<unsigned, Action> lines[] = {
      {17, Action::NextTool}, {27, Action::PrevTool}, {22, Action::SizeUp}, {23, Action::SizeDown}, {24, Action::NextMetal},
      {25, Action::Undo},     {5, Action::Redo},      {6, Action::Turn},    {16, Action::NewSheet}, {26, Action::Staff},
  };
  for (const auto& [line, action] : lines) {
    ButtonLineConfig b;
    b.line = line;
    b.action = action;
    if (action == Action::NewSheet) b.longPress = Action::Staff;
    c.buttons.push_back(b);
  }
  c.chords.push_back({{Action::Undo, Action::Redo}, Action::Staff, 1.0});
  return c;
}

}  // namespace emboss
