// Tests for the button configuration: the documented example parses, and mistakes get messages that say what to fix.
#include <gtest/gtest.h>

#include <fstream>

#include "devices/button_config.h"
#include "test_support.h"

namespace emboss {
namespace {

// The example of docs/hardware.md.
constexpr const char* kExample = R"({
  "chip": "gpiochip0",
  "active_low": true,
  "bias": "pull_up",
  "debounce_ms": 20,
  "long_press_ms": 3000,
  "chord_window_ms": 150,
  "buttons": [
    {"line": 17, "action": "next_tool"},
    {"line": 27, "action": "prev_tool"},
    {"line": 22, "action": "size_up"},
    {"line": 23, "action": "size_down"},
    {"line": 24, "action": "next_metal"},
    {"line": 25, "action": "undo"},
    {"line": 5,  "action": "redo"},
    {"line": 6,  "action": "turn"},
    {"line": 16, "action": "new_sheet", "long_press": "staff"},
    {"line": 26, "action": "staff", "debounce_ms": 50}
  ],
  "chords": [{"buttons": ["undo", "redo"], "action": "staff", "hold_ms": 1000}]
})";

std::string errorOf(const std::string& text) {
  auto c = parseButtonConfig(text, "buttons.json");
  return c ? std::string("(parsed)") : c.error();
}

TEST(ButtonsConfig, TheDocumentedExampleParses) {
  auto c = parseButtonConfig(kExample);
  ASSERT_TRUE(c) << c.error();
  ASSERT_EQ(c->buttons.size(), 10u);
  EXPECT_EQ(c->buttons[0].chip, "gpiochip0");
  EXPECT_EQ(c->buttons[0].line, 17u);
  EXPECT_EQ(c->buttons[0].action, Action::NextTool);
  EXPECT_TRUE(c->buttons[0].activeLow);
  EXPECT_EQ(c->buttons[0].bias, LineBias::PullUp);
  EXPECT_DOUBLE_EQ(c->buttons[0].debounceS, 0.020);
  EXPECT_EQ(c->buttons[8].longPress, Action::Staff);
  EXPECT_DOUBLE_EQ(c->buttons[9].debounceS, 0.050);
  EXPECT_DOUBLE_EQ(c->longPressS, 3.0);
  EXPECT_DOUBLE_EQ(c->chordWindowS, 0.15);
  ASSERT_EQ(c->chords.size(), 1u);
  EXPECT_EQ(c->chords[0].buttons[0], Action::Undo);
  EXPECT_EQ(c->chords[0].buttons[1], Action::Redo);
  EXPECT_EQ(c->chords[0].action, Action::Staff);
  EXPECT_DOUBLE_EQ(c->chords[0].holdS, 1.0);
}

TEST(ButtonsConfig, TheBuiltInDefaultMatchesTheDocumentedExample) {
  auto doc = parseButtonConfig(kExample);
  ASSERT_TRUE(doc) << doc.error();
  const ButtonConfig def = defaultButtonConfig();
  ASSERT_EQ(def.buttons.size(), doc->buttons.size());
  for (size_t i = 0; i < def.buttons.size(); ++i) {
    EXPECT_EQ(def.buttons[i].line, doc->buttons[i].line) << i;
    EXPECT_EQ(def.buttons[i].action, doc->buttons[i].action) << i;
    EXPECT_EQ(def.buttons[i].longPress, doc->buttons[i].longPress) << i;
  }
  ASSERT_EQ(def.chords.size(), 1u);
  EXPECT_DOUBLE_EQ(def.chords[0].holdS, doc->chords[0].holdS);
}

TEST(ButtonsConfig, PerButtonSettingsOverrideTheDefaults) {
  auto c = parseButtonConfig(R"({"bias": "pull_down", "active_low": false,
    "buttons": [{"line": 3, "action": "turn", "chip": "pinctrl-bcm2711", "bias": "disable", "active_low": true}, {"line": 4, "action": "undo"}]})");
  ASSERT_TRUE(c) << c.error();
  EXPECT_EQ(c->buttons[0].chip, "pinctrl-bcm2711");
  EXPECT_EQ(c->buttons[0].bias, LineBias::Disable);
  EXPECT_TRUE(c->buttons[0].activeLow);
  EXPECT_EQ(c->buttons[1].bias, LineBias::PullDown);
  EXPECT_FALSE(c->buttons[1].activeLow);
}

TEST(ButtonsConfig, HowTheLinesAreReadIsAutoEdgesOrLevels) {
  auto plain = parseButtonConfig(R"({"buttons": [{"line": 3, "action": "turn"}]})");
  ASSERT_TRUE(plain) << plain.error();
  EXPECT_EQ(plain->read, GpioRead::Auto);
  for (GpioRead r : {GpioRead::Auto, GpioRead::Edges, GpioRead::Levels}) {
    auto c = parseButtonConfig(std::string(R"({"read": ")") + gpioReadName(r) + R"(", "buttons": [{"line": 3, "action": "turn"}]})");
    ASSERT_TRUE(c) << c.error();
    EXPECT_EQ(c->read, r) << gpioReadName(r);
  }
}

TEST(ButtonsConfig, MistakesSayWhereAndWhat) {
  struct Case {
    const char* text;
    const char* want;
  };
  const Case cases[] = {
      {"{", "buttons.json: not valid JSON"},
      {R"({"debounce_ms": 1e999, "buttons": []})", "buttons.json: not valid JSON"},  // found by fuzz_capture
      {"[]", "expected a JSON object"},
      {"{}", "\"buttons\" must be a non-empty array"},
      {R"({"buttons": [{"line": 17, "action": "nxt_tool"}]})", "buttons[0].action: unknown action 'nxt_tool' (known: next_tool, prev_tool"},
      {R"({"buttons": [{"action": "undo"}]})", "buttons[0].line: missing"},
      {R"({"buttons": [{"line": -1, "action": "undo"}]})", "buttons[0].line: expected a line offset"},
      {R"({"buttons": [{"line": 2.5, "action": "undo"}]})", "buttons[0].line: expected a line offset"},
      {R"({"buttons": [{"line": 2, "action": "undo", "activelow": true}]})", "buttons[0]: unknown key 'activelow'"},
      {R"({"buttons": [{"line": 2, "action": "undo", "bias": "up"}]})", "buttons[0].bias: \"up\" is not one of"},
      {R"({"buttons": [{"line": 2, "action": "undo", "active_low": "yes"}]})", "buttons[0].active_low: expected true or false"},
      {R"({"buttons": [{"line": 2, "action": "undo", "debounce_ms": 5000}]})", "buttons[0].debounce_ms: 5000 is out of range 0..1000 ms"},
      {R"({"buttons": [{"line": 2, "action": "quit"}]})", "'quit' is for the keyboard"},
      {R"({"buttons": [{"line": 2, "action": "undo"}, {"line": 2, "action": "redo"}]})", "buttons[1]: gpiochip0 line 2 is already buttons[0] (undo)"},
      {R"({"long_press_ms": 100, "buttons": [{"line": 2, "action": "undo"}]})", "long_press_ms: 100 is out of range 500..60000 ms"},
      {R"({"buttons": [{"line": 2, "action": "undo"}], "chords": [{"buttons": ["undo", "turn"]}]})",
       "chords[0].buttons[1]: no button has the action 'turn'"},
      {R"({"buttons": [{"line": 2, "action": "undo"}], "chords": [{"buttons": ["undo"]}]})", "chords[0].buttons: expected the actions of two buttons"},
      {R"({"buttons": [{"line": 2, "action": "undo"}, {"line": 3, "action": "undo"}], "chords": [{"buttons": ["undo", "undo"]}]})",
       "several buttons have the action 'undo'"},
      {R"({"buttons": [{"line": 2, "action": "undo"}, {"line": 3, "action": "redo"}, {"line": 4, "action": "turn"}],
          "chords": [{"buttons": ["undo", "redo"]}, {"buttons": ["undo", "turn"]}]})",
       "already in chords[0]"},
      {R"({"buttons": [{"line": 2, "action": "undo"}], "colour": "red"})", "unknown key 'colour'"},
      {R"({"read": "interrupts", "buttons": [{"line": 2, "action": "undo"}]})", "read: \"interrupts\" is not one of \"auto\", \"edges\", \"levels\""},
      {R"({"buttons": [{"line": 2, "action": "undo", "read": "levels"}]})", "buttons[0]: unknown key 'read'"},
  };
  for (const auto& c : cases) {
    const std::string e = errorOf(c.text);
    EXPECT_NE(e.find(c.want), std::string::npos) << "input: " << c.text << "\nmessage: " << e;
  }
}

TEST(ButtonsConfig, LoadingAMissingFileNamesIt) {
  auto c = loadButtonConfig("/nonexistent/buttons.json");
  ASSERT_FALSE(c);
  EXPECT_NE(c.error().find("/nonexistent/buttons.json: cannot read"), std::string::npos) << c.error();
}

TEST(ButtonsConfig, LoadingAFileUsesItsPathInMessages) {
  const auto dir = test::scratchDir("buttons_config");
  std::ofstream(dir / "b.json") << R"({"buttons": [{"line": 1, "action": "bogus"}]})";
  auto c = loadButtonConfig(dir / "b.json");
  ASSERT_FALSE(c);
  EXPECT_NE(c.error().find("b.json: buttons[0].action"), std::string::npos) << c.error();
}

}  // namespace
}  // namespace emboss
