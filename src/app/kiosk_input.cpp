// The kiosk's input: the pen's samples and the buttons, polled and queued, each handed to the
// states, the staff menu or the bench; the bench's pen finding the metal through the renderer.
#include "app/kiosk_app.h"

#include <algorithm>

#include "app/kiosk_app_detail.h"
#include "util/heap_release.h"

namespace emboss {

using namespace kiosk_detail;

void KioskApp::pollInput(double now) {
  if (pen_) {
    std::vector<PenSample> got;
    const bool alive = pen_->poll(got);
    for (const auto& s : got) queue_.push_back({s, now});
    if (!alive) {
      if (log_) log_("pen: '" + pen_->name() + "' stopped answering (unplugged?); the kiosk goes on without it");
      pen_ = nullptr;
      penLost_ = true;
      bench_->penAway();
      lastTip_ = false;
    }
  }
  for (size_t i = 0; i < buttons_.size();) {
    std::vector<ButtonEvent> events;
    const bool alive = buttons_[i]->poll(events);
    for (const auto& e : events) handleButton(e, now);
    if (!alive) {
      if (log_) log_("buttons: '" + buttons_[i]->name() + "' stopped answering; dropped");
      buttons_.erase(buttons_.begin() + static_cast<std::ptrdiff_t>(i));
    } else {
      ++i;
    }
  }
}

void KioskApp::handleEvents(double now) {
  for (KioskEvent ev : states_.takeEvents()) {
    if (log_) log_(std::string("state: ") + kioskEventName(ev) + " (now " + kioskModeName(states_.mode()) + ")");
    switch (ev) {
      case KioskEvent::VisitorArrived:
        bench_->resetForVisitor(now);
        sessionStarted_ = now;
        discardCapture("a new visitor");
        break;
      case KioskEvent::CountdownStarted: bench_->penAway(); break;
      case KioskEvent::VisitorBack: break;
      case KioskEvent::SessionEnded:
        saveSession("the visitor left");
        discardCapture("the visitor left");
        bench_->resetForVisitor(now);
        composer_->release(bench_->model());  // the piece's index and fields go, not only its operations
        startAttract(now, attract_->empty() ? 0 : (attract_->pieceIndex() + 1) % attract_->size(), 0.0);
        releaseFreeHeap();  // a quiet moment: what the visitor's piece held goes back to the system
        break;
      case KioskEvent::StaffEntered:
        bench_->penAway();
        staff_.selected = 0;
        staff_.message.clear();
        break;
      case KioskEvent::StaffLeft: break;
    }
  }
}

void KioskApp::handleButton(const ButtonEvent& e, double now) {
  if (e.action == Action::Quit) {
    if (e.pressed) quit_ = true;
    return;
  }
  const bool act = states_.button(e, now);
  handleEvents(now);
  if (!act || !e.pressed) return;
  switch (states_.mode()) {
    case KioskMode::Staff:
      switch (e.action) {
        case Action::NextTool:
        case Action::SizeDown: staff_.selected = (staff_.selected + 1) % kStaffItems; break;
        case Action::PrevTool:
        case Action::SizeUp: staff_.selected = (staff_.selected + kStaffItems - 1) % kStaffItems; break;
        case Action::Turn:
        case Action::NewSheet:
        case Action::Redo: staffActivate(staff_.selected); break;
        case Action::Undo: staffActivate(0); break;
        case Action::Capture: staffActivate(3); break;
        default: break;
      }
      break;
    case KioskMode::Visitor:
      if (e.action == Action::Capture) {
        if (capture_.phase == CapturePhase::Offer) acceptCapture(now);
        else startCapture(now);
        break;
      }
      if (e.action == Action::Undo && capture_.phase == CapturePhase::Offer) {
        discardCapture("undo");
        captureNote(now, "The drawing was put away", false);
        break;
      }
      if (e.action == Action::NewSheet) {
        saveSession("a new sheet");
        discardCapture("a new sheet");
      }
      bench_->apply(e.action, now);
      break;
    default: break;
  }
}

void KioskApp::connectPicker() {
  if (!pickThroughRenderer_) {
    bench_->setPicker(nullptr);
    return;
  }
  bench_->setPicker([this](const Model& m, const Camera& c, double sx, double sy, std::optional<glm::dvec3>& hit) {
    return composer_->pick(m, c, sx, sy, hit);
  });
}

void KioskApp::handlePen(const PenSample& s, double arrival, double now) {
  // The barrel buttons are buttons (a press wakes the kiosk as any button does).
  const std::pair<bool, Action> barrels[2] = {{s.barrel1 && !lastBarrel1_, config_.penButton1},
                                              {s.barrel2 && !lastBarrel2_, config_.penButton2}};
  lastBarrel1_ = s.barrel1, lastBarrel2_ = s.barrel2;
  for (const auto& [pressed, action] : barrels)
    if (pressed && action != Action::None) {
      handleButton({now, action, true, false}, now);
      handleButton({now, action, false, false}, now);
    }
  const bool down = s.tip && !lastTip_;
  lastTip_ = s.tip;
  const double W = composer_->width(), H = composer_->height();
  if (states_.mode() == KioskMode::Staff) {
    if (!down) return;
    // Staff taps the menu: the whole tablet is the whole screen here.
    const double sx = s.x * W, sy = s.y * H;
    const auto boxes = staffMenuBoxes(composer_->width(), composer_->height(), kStaffItems);
    states_.penTouch(now);
    for (size_t i = 0; i < boxes.size(); ++i)
      if (sx >= boxes[i].x && sx < boxes[i].x + boxes[i].w && sy >= boxes[i].y && sy < boxes[i].y + boxes[i].h) {
        staff_.selected = i;
        staffActivate(i);
        break;
      }
    return;
  }
  if (s.tip) {
    states_.penTouch(now);  // attract -> visitor: the bench is fresh before this very sample embosses
    handleEvents(now);
  }
  if (states_.mode() != KioskMode::Visitor && states_.mode() != KioskMode::StillThere) return;
  double sx, sy;
  if (mapping_ == PenMapping::Screen) {
    sx = s.x * W, sy = s.y * H;
  } else {
    const ScreenBox a = bench_->tabletArea();
    sx = a.x + s.x * a.w, sy = a.y + s.y * a.h;
  }
  bench_->pen(sx, sy, s.pressure, s.tip, s.inRange, now);
  if (bench_->committed() != lastCommitted_) {
    lastCommitted_ = bench_->committed();
    latency_.madeOperation(arrival);
  }
}

}  // namespace emboss
