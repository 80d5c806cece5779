// The kiosk's state machine: attract, visitor, "still there?", staff.
#include "app/kiosk_states.h"

#include <algorithm>

namespace emboss {

const char* kioskModeName(KioskMode m) {
  switch (m) {
    case KioskMode::Attract: return "attract";
    case KioskMode::Visitor: return "visitor";
    case KioskMode::StillThere: return "still-there";
    case KioskMode::Staff: return "staff";
  }
  return "?";
}

const char* kioskEventName(KioskEvent e) {
  switch (e) {
    case KioskEvent::VisitorArrived: return "visitor-arrived";
    case KioskEvent::CountdownStarted: return "countdown-started";
    case KioskEvent::VisitorBack: return "visitor-back";
    case KioskEvent::SessionEnded: return "session-ended";
    case KioskEvent::StaffEntered: return "staff-entered";
    case KioskEvent::StaffLeft: return "staff-left";
  }
  return "?";
}

KioskStates::KioskStates(KioskTimings timings, std::pair<Action, Action> staffChord, double now, KioskMode start)
    : t_(timings), chord_(staffChord), mode_(start), lastActivity_(now) {
  if (start == KioskMode::Staff) beforeStaff_ = KioskMode::Attract;
  if (start == KioskMode::StillThere) mode_ = KioskMode::Visitor;
}

void KioskStates::set(KioskMode m, double now) {
  mode_ = m;
  if (m == KioskMode::StillThere) countdownStart_ = now;
}

void KioskStates::activity(double now) { lastActivity_ = now; }

void KioskStates::penTouch(double now) {
  activity(now);
  switch (mode_) {
    case KioskMode::Attract:
      set(KioskMode::Visitor, now);
      events_.push_back(KioskEvent::VisitorArrived);
      break;
    case KioskMode::StillThere:
      set(KioskMode::Visitor, now);
      events_.push_back(KioskEvent::VisitorBack);
      break;
    case KioskMode::Visitor:
    case KioskMode::Staff: break;
  }
}

bool KioskStates::button(const ButtonEvent& e, double now) {
  if (e.action == Action::None) return false;
  if (!e.pressed) {
    held_.erase(e.action);
    if (!(held_.count(chord_.first) && held_.count(chord_.second))) chordSince_ = -1, chordUsed_ = false;
    return false;
  }
  held_.insert(e.action);
  activity(now);
  if (held_.count(chord_.first) && held_.count(chord_.second) && chordSince_ < 0) chordSince_ = now;
  if (e.action == Action::Staff) {
    if (mode_ != KioskMode::Staff) enterStaff(now);
    return false;
  }
  if (e.action == Action::Quit) return true;
  switch (mode_) {
    case KioskMode::Attract:
      set(KioskMode::Visitor, now);
      events_.push_back(KioskEvent::VisitorArrived);
      return true;  // the press that wakes the kiosk also does what it says
    case KioskMode::StillThere:
      set(KioskMode::Visitor, now);
      events_.push_back(KioskEvent::VisitorBack);
      return false;  // it answered the question
    case KioskMode::Visitor:
    case KioskMode::Staff: return true;
  }
  return true;
}

void KioskStates::tick(double now) {
  if (chordSince_ >= 0 && !chordUsed_ && now - chordSince_ >= t_.chordSeconds) {
    chordUsed_ = true;
    if (mode_ != KioskMode::Staff) enterStaff(now);
  }
  switch (mode_) {
    case KioskMode::Visitor:
      if (now - lastActivity_ >= t_.idleSeconds) {
        set(KioskMode::StillThere, now);
        events_.push_back(KioskEvent::CountdownStarted);
      }
      break;
    case KioskMode::StillThere:
      if (now - countdownStart_ >= t_.countdownSeconds) {
        set(KioskMode::Attract, now);
        events_.push_back(KioskEvent::SessionEnded);
      }
      break;
    case KioskMode::Staff:
      if (now - lastActivity_ >= t_.staffIdleSeconds) leaveStaff(now);
      break;
    case KioskMode::Attract: break;
  }
}

void KioskStates::enterStaff(double now) {
  if (mode_ == KioskMode::Staff) return;
  beforeStaff_ = mode_ == KioskMode::StillThere ? KioskMode::Visitor : mode_;
  activity(now);
  set(KioskMode::Staff, now);
  events_.push_back(KioskEvent::StaffEntered);
}

void KioskStates::leaveStaff(double now) {
  if (mode_ != KioskMode::Staff) return;
  activity(now);  // a visitor left mid-session gets the full idle time again
  set(beforeStaff_, now);
  events_.push_back(KioskEvent::StaffLeft);
}

void KioskStates::resetToAttract(double now) {
  const KioskMode from = mode_ == KioskMode::Staff ? beforeStaff_ : mode_;
  if (mode_ == KioskMode::Staff) events_.push_back(KioskEvent::StaffLeft);
  activity(now);
  beforeStaff_ = KioskMode::Attract;
  set(KioskMode::Attract, now);
  if (from == KioskMode::Visitor || from == KioskMode::StillThere) events_.push_back(KioskEvent::SessionEnded);
}

double KioskStates::countdownLeft(double now) const {
  if (mode_ != KioskMode::StillThere) return 0.0;
  return std::max(0.0, t_.countdownSeconds - (now - countdownStart_));
}

std::vector<KioskEvent> KioskStates::takeEvents() {
  std::vector<KioskEvent> out;
  out.swap(events_);
  return out;
}

}  // namespace emboss
