// Frame rate and stroke-to-screen latency.
#include "app/frame_meter.h"

#include <algorithm>
#include <cmath>

namespace emboss {

void LatencyMeter::madeOperation(double arrival) {
  if (pending_) {
    since_ = std::min(since_, arrival);
  } else {
    pending_ = true;
    since_ = arrival;
  }
}

void LatencyMeter::presented(double now) {
  if (!pending_) return;
  pending_ = false;
  const double ms = std::max(0.0, (now - since_) * 1000.0);
  ++count_;
  sumMs_ += ms;
  maxMs_ = std::max(maxMs_, ms);
  if (ms_.size() < kWindow) {
    ms_.push_back(ms);
  } else {
    ms_[next_] = ms;
    next_ = (next_ + 1) % kWindow;
  }
}

double LatencyMeter::percentileMs(double p) const {
  if (ms_.empty()) return 0.0;
  std::vector<double> v = ms_;
  std::sort(v.begin(), v.end());
  const double k = std::clamp(p, 0.0, 100.0) / 100.0 * (v.size() - 1);
  const size_t i = static_cast<size_t>(std::floor(k));
  const size_t j = std::min(i + 1, v.size() - 1);
  return v[i] + (v[j] - v[i]) * (k - i);
}

void FpsMeter::frame(double now) {
  ++frames_;
  if (havePrev_) intervalSum_ += now - prev_, ++intervals_;
  prev_ = now, havePrev_ = true;
  recent_.push_back(now);
  while (!recent_.empty() && now - recent_.front() > 5.0) recent_.pop_front();
}

double FpsMeter::recentFps(double now) const {
  size_t n = 0;
  for (double t : recent_)
    if (now - t <= 5.0) ++n;
  return n / 5.0;
}

}  // namespace emboss
