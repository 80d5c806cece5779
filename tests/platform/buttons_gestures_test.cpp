// Tests for the button gestures with synthetic edges and a fake clock: debounce, long press, chords.
#include <gtest/gtest.h>

#include "devices/button_config.h"
#include "devices/button_gestures.h"

namespace emboss {
namespace {

ButtonConfig config() {
  ButtonConfig c;
  auto add = [&](unsigned line, Action a, Action longPress = Action::None) {
    ButtonLineConfig b;
    b.line = line;
    b.action = a;
    b.longPress = longPress;
    b.debounceS = 0.020;
    c.buttons.push_back(b);
  };
  add(17, Action::NextTool);                  // 0: plain
  add(16, Action::NewSheet, Action::Staff);  // 1: long press -> staff
  add(25, Action::Undo);                      // 2: chord member
  add(5, Action::Redo);                       // 3: chord member
  c.chords.push_back({{Action::Undo, Action::Redo}, Action::Staff, 0.0});
  c.longPressS = 3.0;
  c.chordWindowS = 0.15;
  return c;
}

// A button bouncing: `n` short flips of 1 ms around the edge at t, ending at `level`.
void bounce(ButtonGestures& g, size_t b, bool level, double t, std::vector<ButtonEvent>& out, int n = 4) {
  for (int i = 0; i < n; ++i) g.edge(b, i % 2 == 0 ? level : !level, t + 0.001 * i, out);
  g.edge(b, level, t + 0.001 * n, out);
}

TEST(ButtonGestures, ABouncyPressIsOnePressAndOneRelease) {
  ButtonGestures g(config());
  std::vector<ButtonEvent> out;
  bounce(g, 0, true, 1.000, out);
  g.advance(1.010, out);
  EXPECT_TRUE(out.empty()) << "nothing before the level has held for the debounce time";
  g.advance(1.030, out);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].action, Action::NextTool);
  EXPECT_TRUE(out[0].pressed);
  EXPECT_DOUBLE_EQ(out[0].time_s, 1.004);  // stamped when the level settled
  bounce(g, 0, false, 1.200, out);
  g.advance(1.300, out);
  ASSERT_EQ(out.size(), 2u);
  EXPECT_EQ(out[1].action, Action::NextTool);
  EXPECT_FALSE(out[1].pressed);
  EXPECT_TRUE(g.nextDeadline() == std::nullopt);
}

TEST(ButtonGestures, AGlitchShorterThanTheDebounceIsIgnored) {
  ButtonGestures g(config());
  std::vector<ButtonEvent> out;
  g.edge(0, true, 2.000, out);
  g.edge(0, false, 2.008, out);  // an 8 ms spike on a long cable
  g.advance(3.0, out);
  EXPECT_TRUE(out.empty());
  EXPECT_FALSE(g.pressed(0));
}

TEST(ButtonGestures, EventsDoNotDependOnHowOftenThePollerRuns) {
  // The same edges, advanced every millisecond or once at the end, give the same events.
  std::vector<ButtonEvent> fine, coarse;
  ButtonGestures a(config()), b(config());
  const std::vector<std::tuple<size_t, bool, double>> edges = {
      {0, true, 0.10}, {0, false, 0.30}, {1, true, 0.50}, {1, false, 0.90}, {1, true, 1.00}, {1, false, 4.50}};
  double t = 0;
  for (const auto& [btn, level, at] : edges) {
    for (; t < at; t += 0.001) a.advance(t, fine);
    a.edge(btn, level, at, fine);
    b.edge(btn, level, at, coarse);
  }
  a.advance(6.0, fine);
  b.advance(6.0, coarse);
  ASSERT_EQ(fine.size(), coarse.size());
  for (size_t i = 0; i < fine.size(); ++i) {
    EXPECT_EQ(fine[i].action, coarse[i].action);
    EXPECT_EQ(fine[i].pressed, coarse[i].pressed);
    EXPECT_DOUBLE_EQ(fine[i].time_s, coarse[i].time_s);
  }
}

TEST(ButtonGestures, AShortPressOfALongPressButtonIsItsOwnActionOnRelease) {
  ButtonGestures g(config());
  std::vector<ButtonEvent> out;
  g.edge(1, true, 5.0, out);
  g.advance(5.5, out);
  EXPECT_TRUE(out.empty()) << "a long-press button waits to see whether it is held";
  g.edge(1, false, 5.8, out);
  g.advance(6.0, out);
  ASSERT_EQ(out.size(), 2u);
  EXPECT_EQ(out[0].action, Action::NewSheet);
  EXPECT_TRUE(out[0].pressed);
  EXPECT_DOUBLE_EQ(out[0].time_s, 5.0);
  EXPECT_FALSE(out[0].longPress);
  EXPECT_EQ(out[1].action, Action::NewSheet);
  EXPECT_FALSE(out[1].pressed);
}

TEST(ButtonGestures, HoldingThreeSecondsEntersStaffMode) {
  ButtonGestures g(config());
  std::vector<ButtonEvent> out;
  g.edge(1, true, 10.0, out);
  g.advance(12.9, out);
  EXPECT_TRUE(out.empty());
  ASSERT_TRUE(g.nextDeadline());
  EXPECT_DOUBLE_EQ(*g.nextDeadline(), 13.0);
  g.advance(13.0, out);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].action, Action::Staff);
  EXPECT_TRUE(out[0].pressed);
  EXPECT_TRUE(out[0].longPress);
  EXPECT_DOUBLE_EQ(out[0].time_s, 13.0);
  g.edge(1, false, 14.0, out);
  g.advance(15.0, out);
  ASSERT_EQ(out.size(), 2u);
  EXPECT_EQ(out[1].action, Action::Staff);
  EXPECT_FALSE(out[1].pressed);
  for (const auto& e : out) EXPECT_NE(e.action, Action::NewSheet) << "a long press must not also start a new sheet";
}

TEST(ButtonGestures, TwoButtonsTogetherAreTheChordAlone) {
  ButtonGestures g(config());
  std::vector<ButtonEvent> out;
  g.edge(2, true, 20.00, out);
  g.edge(3, true, 20.08, out);  // 80 ms later: together
  g.advance(20.2, out);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].action, Action::Staff);
  EXPECT_TRUE(out[0].pressed);
  EXPECT_DOUBLE_EQ(out[0].time_s, 20.08);
  g.edge(2, false, 21.0, out);
  g.edge(3, false, 21.1, out);
  g.advance(22.0, out);
  ASSERT_EQ(out.size(), 2u);
  EXPECT_EQ(out[1].action, Action::Staff);
  EXPECT_FALSE(out[1].pressed);
  for (const auto& e : out) EXPECT_TRUE(e.action == Action::Staff) << "no undo or redo leaks out of a chord";
}

TEST(ButtonGestures, AChordMemberAloneActsAfterTheWindow) {
  ButtonGestures g(config());
  std::vector<ButtonEvent> out;
  g.edge(2, true, 30.0, out);
  g.advance(30.1, out);
  EXPECT_TRUE(out.empty());
  g.advance(30.2, out);  // window 0.15 + debounce 0.02
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].action, Action::Undo);
  EXPECT_DOUBLE_EQ(out[0].time_s, 30.0);
  // The partner pressed late is just a redo.
  g.edge(3, true, 30.5, out);
  g.advance(31.0, out);
  ASSERT_EQ(out.size(), 2u);
  EXPECT_EQ(out[1].action, Action::Redo);
}

TEST(ButtonGestures, AQuickTapOfAChordMemberStillCounts) {
  ButtonGestures g(config());
  std::vector<ButtonEvent> out;
  g.edge(3, true, 40.00, out);
  g.edge(3, false, 40.06, out);
  g.advance(41.0, out);
  ASSERT_EQ(out.size(), 2u);
  EXPECT_EQ(out[0].action, Action::Redo);
  EXPECT_TRUE(out[0].pressed);
  EXPECT_EQ(out[1].action, Action::Redo);
  EXPECT_FALSE(out[1].pressed);
}

TEST(ButtonGestures, AChordWithAHoldTimeNeedsBothHeld) {
  ButtonConfig c = config();
  c.chords[0].holdS = 1.0;
  ButtonGestures g(c);
  std::vector<ButtonEvent> out;
  // Released early: nothing at all.
  g.edge(2, true, 50.0, out);
  g.edge(3, true, 50.05, out);
  g.edge(3, false, 50.5, out);
  g.edge(2, false, 50.6, out);
  g.advance(52.0, out);
  EXPECT_TRUE(out.empty());
  // Held: the chord after one second.
  g.edge(2, true, 60.0, out);
  g.edge(3, true, 60.05, out);
  g.advance(61.0, out);
  EXPECT_TRUE(out.empty());
  g.advance(61.1, out);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].action, Action::Staff);
  EXPECT_DOUBLE_EQ(out[0].time_s, 61.05);
}

TEST(ButtonGestures, AButtonHeldAtStartIsIgnoredUntilReleased) {
  ButtonGestures g(config());
  std::vector<ButtonEvent> out;
  g.reset(0, true, 0.0);
  g.edge(0, false, 1.0, out);
  g.advance(2.0, out);
  EXPECT_TRUE(out.empty());
  g.edge(0, true, 3.0, out);
  g.advance(3.1, out);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].action, Action::NextTool);
}

TEST(ButtonGestures, ZeroDebounceActsAtOnce) {
  ButtonConfig c = config();
  c.buttons[0].debounceS = 0;
  ButtonGestures g(c);
  std::vector<ButtonEvent> out;
  g.edge(0, true, 1.0, out);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_DOUBLE_EQ(out[0].time_s, 1.0);
}

}  // namespace
}  // namespace emboss
