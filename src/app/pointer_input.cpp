// Mouse and keyboard as pen and buttons.
#include "app/pointer_input.h"

#include <algorithm>

namespace emboss {

MousePen::MousePen(int width, int height, Clock now) : w_(std::max(1, width)), h_(std::max(1, height)), now_(std::move(now)) {}

double MousePen::pressureAt(double t) const {
  const double ramp = std::clamp((t - downAt_) / 0.15, 0.0, 1.0);
  return std::clamp(level_ * (0.75 + 0.25 * ramp), 0.05, 1.0);
}

void MousePen::feed(const PointerEvent& e) {
  const double t = now_();
  switch (e.type) {
    case PointerEvent::Type::Key:
      if (e.key == "bracketleft") level_ = std::max(0.1, level_ - 0.1);
      if (e.key == "bracketright") level_ = std::min(1.0, level_ + 0.1);
      return;
    case PointerEvent::Type::Leave:
      inside_ = false;
      down_ = false;
      break;
    case PointerEvent::Type::Down:
      down_ = true;
      downAt_ = t;
      inside_ = true;
      x_ = e.x, y_ = e.y;
      break;
    case PointerEvent::Type::Up:
      down_ = false;
      x_ = e.x, y_ = e.y;
      break;
    case PointerEvent::Type::Move:
      inside_ = true;
      x_ = e.x, y_ = e.y;
      break;
  }
  PenSample s;
  s.time_s = t;
  s.x = std::clamp(x_ / w_, 0.0, 1.0);
  s.y = std::clamp(y_ / h_, 0.0, 1.0);
  s.tip = down_;
  s.inRange = inside_ || down_;
  s.pressure = down_ ? pressureAt(t) : 0.0;
  out_.push_back(s);
}

bool MousePen::poll(std::vector<PenSample>& out) {
  out.insert(out.end(), out_.begin(), out_.end());
  out_.clear();
  return true;
}

KeyButtons::KeyButtons(std::map<std::string, Action> keys, Clock now) : keys_(std::move(keys)), now_(std::move(now)) {}

void KeyButtons::feed(const PointerEvent& e) {
  if (e.type != PointerEvent::Type::Key) return;
  const auto it = keys_.find(e.key);
  if (it == keys_.end() || it->second == Action::None) return;
  const double t = now_();
  out_.push_back({t, it->second, true, false});
  out_.push_back({t, it->second, false, false});
}

bool KeyButtons::poll(std::vector<ButtonEvent>& out) {
  out.insert(out.end(), out_.begin(), out_.end());
  out_.clear();
  return true;
}

}  // namespace emboss
