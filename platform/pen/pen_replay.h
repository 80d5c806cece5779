// The replay pen: a PenSource playing recorded samples (evemu, hid-recorder) in real time or at once.
#pragma once

#include <cstddef>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "devices/pen.h"
#include "platform_util.h"
#include "util/result.h"

namespace emboss {

class ReplayPen final : public PenSource {
 public:
  using Clock = std::function<double()>;

  // Plays samples (sorted by time_s) against now (seconds, default CLOCK_MONOTONIC): the first
  // poll() starts the clock, and sample i comes out once now() - start >= time_s[i] - time_s[0].
  // With fast, the first poll() hands out every sample. Samples keep their recorded time_s.
  ReplayPen(std::vector<PenSample> samples, std::string name, bool fast, Clock now = {});

  std::string name() const override { return name_; }
  bool poll(std::vector<PenSample>& out) override;  // never false: a recording cannot be unplugged
  bool finished() const override { return next_ >= samples_.size(); }
  // When the next sample is due: 0 before the first poll() and when fed as fast as possible,
  // infinity once every sample is out.
  double pollWithin() const override;

  size_t played() const { return next_; }
  size_t size() const { return samples_.size(); }

 private:
  std::vector<PenSample> samples_;
  std::string name_;
  bool fast_ = false;
  Clock now_;
  bool started_ = false;
  double start_ = 0.0;
  size_t next_ = 0;
};

// The kiosk's --tablet=evemu:PATH: loads an evemu .events recording (finding its .desc beside it
// when the file lacks its own description) and replays it.
Result<std::unique_ptr<PenSource>> openEvemuReplay(const std::filesystem::path& events, bool fast);

// The same for a hid-recorder capture, decoded as the hidraw back end would.
Result<std::unique_ptr<PenSource>> openHidRecordReplay(const std::filesystem::path& capture, bool fast);

}  // namespace emboss
