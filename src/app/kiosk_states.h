// The kiosk's states (attract, visitor, "still there?", staff) as pure logic over an injected clock.
#pragma once

#include <set>
#include <utility>
#include <vector>

#include "devices/buttons.h"

namespace emboss {

enum class KioskMode { Attract, Visitor, StillThere, Staff };
const char* kioskModeName(KioskMode m);

struct KioskTimings {
  double idleSeconds = 60;        // visitor without a touch or a press -> "still there?"
  double countdownSeconds = 15;   // "still there?" unanswered -> session saved, attract
  double staffIdleSeconds = 300;  // staff mode untouched -> back where it was entered from
  double chordSeconds = 3;        // the staff chord held this long -> staff mode
};

// What the app must do after a change of state. Returned in order by takeEvents().
enum class KioskEvent {
  VisitorArrived,    // attract -> visitor: hand out a fresh sheet (the waking touch then embosses)
  CountdownStarted,  // visitor idle: show "still there?"
  VisitorBack,       // the countdown was answered; the session goes on
  SessionEnded,      // save the visitor's session; attract resumes
  StaffEntered,
  StaffLeft,         // back to the mode staff mode was entered from (see mode())
};
const char* kioskEventName(KioskEvent e);

// Times are seconds on one monotonic clock, passed in by the caller (tests use a fake one). Only
// touches of the pen and button presses count as a visitor's activity: a pen left hovering in
// range must not keep a session open forever.
class KioskStates {
 public:
  KioskStates(KioskTimings timings, std::pair<Action, Action> staffChord, double now, KioskMode start = KioskMode::Attract);

  KioskMode mode() const { return mode_; }

  // The pen touched the surface (or is still touching).
  void penTouch(double now);
  // A button changed. Returns true when the app should carry out its action (in staff mode: on the
  // staff menu); false when the state machine used it up (a release, the answer to "still
  // there?", a chord that opened staff mode, Action::Staff).
  bool button(const ButtonEvent& e, double now);
  // Advances timers: idle, countdown, staff idle, a chord held long enough.
  void tick(double now);

  void enterStaff(double now);
  // Staff "resume": back to where staff mode was entered from.
  void leaveStaff(double now);
  // Staff "reset": the visitor's session (if any) ends, attract resumes.
  void resetToAttract(double now);
  // A visitor's session brought back at start (the kiosk stopped in the middle of it): visitor
  // mode at once, without the VisitorArrived event that would give them a fresh sheet.
  void resumeVisitor(double now) {
    activity(now);
    set(KioskMode::Visitor, now);
  }

  // Seconds left on the "still there?" countdown (0 outside it).
  double countdownLeft(double now) const;
  // Seconds since the last touch or press.
  double idleFor(double now) const { return now - lastActivity_; }
  // The mode staff mode returns to.
  KioskMode modeBeforeStaff() const { return beforeStaff_; }

  std::vector<KioskEvent> takeEvents();

 private:
  void activity(double now);
  void set(KioskMode m, double now);

  KioskTimings t_;
  std::pair<Action, Action> chord_;
  KioskMode mode_;
  KioskMode beforeStaff_ = KioskMode::Attract;
  double lastActivity_ = 0;
  double countdownStart_ = 0;
  double chordSince_ = -1;  // < 0: the chord is not held
  bool chordUsed_ = false;  // the current hold already opened staff mode
  std::set<Action> held_;
  std::vector<KioskEvent> events_;
};

}  // namespace emboss
