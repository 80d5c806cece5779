// The kiosk's state machine under a fake clock: attract, visitor, "still there?", staff.
#include <gtest/gtest.h>

#include "app/kiosk_states.h"

namespace emboss {
namespace {

constexpr KioskTimings kT{60, 15, 300, 3};
const std::pair<Action, Action> kChord{Action::Undo, Action::Redo};

ButtonEvent press(Action a, double t) { return {t, a, true, false}; }
ButtonEvent release(Action a, double t) { return {t, a, false, false}; }

TEST(KioskStates, StartsInAttractAndATouchHandsOverAtOnce) {
  KioskStates s(kT, kChord, 0.0);
  EXPECT_EQ(s.mode(), KioskMode::Attract);
  s.tick(1000);
  EXPECT_EQ(s.mode(), KioskMode::Attract);  // attract never times out
  s.penTouch(1000.5);
  EXPECT_EQ(s.mode(), KioskMode::Visitor);
  EXPECT_EQ(s.takeEvents(), std::vector<KioskEvent>{KioskEvent::VisitorArrived});
  s.penTouch(1000.6);  // the same stroke goes on: no second arrival
  EXPECT_TRUE(s.takeEvents().empty());
}

TEST(KioskStates, AButtonWakesTheKioskAndIsCarriedOut) {
  KioskStates s(kT, kChord, 0.0);
  EXPECT_TRUE(s.button(press(Action::NextTool, 5), 5));
  EXPECT_EQ(s.mode(), KioskMode::Visitor);
  EXPECT_EQ(s.takeEvents(), std::vector<KioskEvent>{KioskEvent::VisitorArrived});
  EXPECT_FALSE(s.button(release(Action::NextTool, 5.1), 5.1));  // releases never act
}

TEST(KioskStates, IdleVisitorIsAskedThenTheSessionEnds) {
  KioskStates s(kT, kChord, 0.0);
  s.penTouch(10);
  s.takeEvents();
  s.tick(69.9);
  EXPECT_EQ(s.mode(), KioskMode::Visitor);
  s.tick(70.0);
  EXPECT_EQ(s.mode(), KioskMode::StillThere);
  EXPECT_EQ(s.takeEvents(), std::vector<KioskEvent>{KioskEvent::CountdownStarted});
  EXPECT_DOUBLE_EQ(s.countdownLeft(75.0), 10.0);
  s.tick(84.9);
  EXPECT_EQ(s.mode(), KioskMode::StillThere);
  s.tick(85.0);
  EXPECT_EQ(s.mode(), KioskMode::Attract);
  EXPECT_EQ(s.takeEvents(), std::vector<KioskEvent>{KioskEvent::SessionEnded});
  EXPECT_DOUBLE_EQ(s.countdownLeft(86), 0.0);
}

TEST(KioskStates, ActivityKeepsTheVisitorAndAnswersTheCountdown) {
  KioskStates s(kT, kChord, 0.0);
  s.penTouch(0);
  s.tick(50);
  s.button(press(Action::SizeUp, 50), 50);  // activity at 50: idle counts from here
  s.tick(109);
  EXPECT_EQ(s.mode(), KioskMode::Visitor);
  s.tick(110);
  EXPECT_EQ(s.mode(), KioskMode::StillThere);
  s.takeEvents();
  // A press answers "still there?" and is not carried out as an action.
  EXPECT_FALSE(s.button(press(Action::NewSheet, 112), 112));
  EXPECT_EQ(s.mode(), KioskMode::Visitor);
  EXPECT_EQ(s.takeEvents(), std::vector<KioskEvent>{KioskEvent::VisitorBack});
  s.tick(172);
  s.takeEvents();
  EXPECT_EQ(s.mode(), KioskMode::StillThere);
  s.penTouch(173);  // a touch answers too (and the bench takes the stroke)
  EXPECT_EQ(s.mode(), KioskMode::Visitor);
  EXPECT_EQ(s.takeEvents(), std::vector<KioskEvent>{KioskEvent::VisitorBack});
}

TEST(KioskStates, HeldChordOpensStaffModeAndShortChordDoesNot) {
  KioskStates s(kT, kChord, 0.0);
  s.penTouch(1);
  s.takeEvents();
  s.button(press(Action::Undo, 10), 10);
  s.button(press(Action::Redo, 10.1), 10.1);
  s.tick(12.0);
  s.button(release(Action::Redo, 12.5), 12.5);  // let go before 3 s
  s.tick(20);
  EXPECT_EQ(s.mode(), KioskMode::Visitor);
  s.button(press(Action::Redo, 21), 21);  // undo still held: the chord starts again
  s.tick(23.9);
  EXPECT_EQ(s.mode(), KioskMode::Visitor);
  s.tick(24.0);
  EXPECT_EQ(s.mode(), KioskMode::Staff);
  EXPECT_EQ(s.modeBeforeStaff(), KioskMode::Visitor);
  EXPECT_EQ(s.takeEvents(), std::vector<KioskEvent>{KioskEvent::StaffEntered});
  // Staying held does not re-enter; leaving goes back to the visitor with a fresh idle time.
  s.tick(30);
  s.leaveStaff(31);
  EXPECT_EQ(s.mode(), KioskMode::Visitor);
  EXPECT_EQ(s.takeEvents(), std::vector<KioskEvent>{KioskEvent::StaffLeft});
  s.tick(90);
  EXPECT_EQ(s.mode(), KioskMode::Visitor);
  s.tick(91);
  EXPECT_EQ(s.mode(), KioskMode::StillThere);
}

TEST(KioskStates, StaffActionEntersAndStaffTimesOut) {
  KioskStates s(kT, kChord, 0.0);
  EXPECT_FALSE(s.button(press(Action::Staff, 5), 5));
  EXPECT_EQ(s.mode(), KioskMode::Staff);
  EXPECT_EQ(s.modeBeforeStaff(), KioskMode::Attract);
  EXPECT_TRUE(s.button(press(Action::NextTool, 6), 6));  // for the staff menu
  s.tick(305.9);
  EXPECT_EQ(s.mode(), KioskMode::Staff);
  s.tick(306);
  EXPECT_EQ(s.mode(), KioskMode::Attract);
}

TEST(KioskStates, StaffResetEndsTheVisitorsSession) {
  KioskStates s(kT, kChord, 0.0);
  s.penTouch(1);
  s.tick(70);  // still there?
  s.enterStaff(72);
  EXPECT_EQ(s.modeBeforeStaff(), KioskMode::Visitor);
  s.takeEvents();
  s.resetToAttract(73);
  EXPECT_EQ(s.mode(), KioskMode::Attract);
  EXPECT_EQ(s.takeEvents(), (std::vector<KioskEvent>{KioskEvent::StaffLeft, KioskEvent::SessionEnded}));
  // From attract there is no session to end.
  s.enterStaff(80);
  s.takeEvents();
  s.resetToAttract(81);
  EXPECT_EQ(s.takeEvents(), std::vector<KioskEvent>{KioskEvent::StaffLeft});
}

TEST(KioskStates, StartInStaffMode) {
  KioskStates s(kT, kChord, 0.0);
  s.enterStaff(0);
  EXPECT_EQ(s.mode(), KioskMode::Staff);
  s.leaveStaff(1);
  EXPECT_EQ(s.mode(), KioskMode::Attract);
}

}  // namespace
}  // namespace emboss
