// Names of the button actions, as used in configuration files and logs.
#include "devices/buttons.h"

#include <array>
#include <utility>

namespace emboss {

namespace {
constexpr std::array<std::pair<Action, const char*>, 13> kNames = {{
    {Action::None, "none"},         {Action::NextTool, "next_tool"}, {Action::PrevTool, "prev_tool"},
    {Action::SizeUp, "size_up"},    {Action::SizeDown, "size_down"}, {Action::NextMetal, "next_metal"},
    {Action::Undo, "undo"},         {Action::Redo, "redo"},          {Action::Turn, "turn"},
    {Action::NewSheet, "new_sheet"}, {Action::Capture, "capture"},   {Action::Staff, "staff"},
    {Action::Quit, "quit"},
}};
}  // namespace

const char* actionName(Action a) {
  for (const auto& [action, name] : kNames)
    if (action == a) return name;
  return "none";
}

Action actionFromName(const std::string& name) {
  for (const auto& [action, n] : kNames)
    if (name == n) return action;
  return Action::None;
}

}  // namespace emboss
