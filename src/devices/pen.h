// The pen: samples from a pressure tablet (real, replayed or the mouse), normalised to the tablet.
#pragma once

#include <limits>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "devices/poll_pace.h"

namespace emboss {

// One pen sample. x and y run 0..1 across the tablet's active area (x right, y down, as the device
// reports them); pressure runs 0..1. time_s is seconds on the source's own clock (for a recording,
// the recording's time stamps; for a live device, CLOCK_MONOTONIC).
struct PenSample {
  double time_s = 0.0;
  double x = 0.0;
  double y = 0.0;
  double pressure = 0.0;
  bool tip = false;      // the tip touches the surface
  bool inRange = false;  // the pen is in proximity (hovering or touching)
  bool barrel1 = false;
  bool barrel2 = false;
};

// A source of pen samples. poll() never blocks; the main loop waits on fd() where there is one.
// Thread-safety: one thread (the main loop) uses a source.
class PenSource {
 public:
  virtual ~PenSource() = default;
  // What this source is, for the log and the staff screen ("evdev: Wacom Intuos4 6x9 Pen").
  virtual std::string name() const = 0;
  // Appends the samples available now. Returns false when the device is gone (unplugged); the
  // caller then drops it and asks the back ends again.
  virtual bool poll(std::vector<PenSample>& out) = 0;
  // A file descriptor to wait on, or -1 when the source must be polled.
  virtual int fd() const { return -1; }
  // Within how many seconds from now poll() must be called again when fd() has not become readable
  // meanwhile: never (infinity) for a source with a descriptor, kPollPaceS for one that must be
  // polled; a recording knows when its next sample is due.
  virtual double pollWithin() const { return fd() >= 0 ? std::numeric_limits<double>::infinity() : kPollPaceS; }
  // True when a recording has been played to its end.
  virtual bool finished() const { return false; }
};

// Pen samples handed in by the program itself (the soak benchmark, tests), taken at the next poll.
class QueuedPen final : public PenSource {
 public:
  explicit QueuedPen(std::string name = "queued pen") : name_(std::move(name)) {}
  std::string name() const override { return name_; }
  bool poll(std::vector<PenSample>& out) override {
    out.insert(out.end(), queued.begin(), queued.end());
    queued.clear();
    return true;
  }
  std::vector<PenSample> queued;

 private:
  std::string name_;
};

}  // namespace emboss
