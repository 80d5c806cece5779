// Measures what a visitor feels: frames per second per mode and stroke-to-screen latency.
#pragma once

#include <cstddef>
#include <deque>
#include <string>
#include <vector>

namespace emboss {

// Latency: from the moment a pen event reached the kiosk (polled from the device, or, for a
// recording fed with --fast, taken from the queue) to the moment the frame that first shows the
// operation it made was presented. Only events that made an operation count.
class LatencyMeter {
 public:
  // An event that made operations, arrived at `arrival` (seconds). The earliest unshown one is kept.
  void madeOperation(double arrival);
  // A frame with the model's changes was presented at `now`.
  void presented(double now);
  // Count, mean and max cover every update since the kiosk started; the percentiles the last
  // kWindow updates (the kiosk runs for months: what it keeps must not grow with its strokes).
  static constexpr size_t kWindow = 4096;
  size_t count() const { return count_; }
  double meanMs() const { return count_ ? sumMs_ / double(count_) : 0.0; }
  double percentileMs(double p) const;  // p in 0..100
  double maxMs() const { return maxMs_; }
  size_t kept() const { return ms_.size(); }  // updates held for the percentiles, at most kWindow

 private:
  bool pending_ = false;
  double since_ = 0;
  size_t count_ = 0;
  double sumMs_ = 0, maxMs_ = 0;
  std::vector<double> ms_;  // a ring of the last kWindow updates; next_ is the oldest once full
  size_t next_ = 0;
};

// Frames presented per second, in total for a mode and over the last few seconds.
class FpsMeter {
 public:
  void frame(double now);
  // The mode was left: the next frame starts a new stretch (the time between is not a frame's).
  void pause() { havePrev_ = false; }
  // Frames a second between each stretch's first and last frames: the pace the screen moved at
  // once it showed the mode (what starting up, or loading before the first frame, took is not in it).
  double paceFps() const { return intervalSum_ > 0 ? static_cast<double>(intervals_) / intervalSum_ : 0.0; }
  size_t intervals() const { return intervals_; }
  double intervalSeconds() const { return intervalSum_; }
  // Adds time spent in the mode (called every loop iteration with the time since the last).
  void time(double seconds) { seconds_ += seconds; }
  double meanFps() const { return seconds_ > 0 ? frames_ / seconds_ : 0.0; }
  double recentFps(double now) const;
  size_t frames() const { return frames_; }
  double seconds() const { return seconds_; }

 private:
  size_t frames_ = 0;
  double seconds_ = 0;
  bool havePrev_ = false;
  double prev_ = 0, intervalSum_ = 0;
  size_t intervals_ = 0;
  std::deque<double> recent_;
};

}  // namespace emboss
