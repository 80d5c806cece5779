// The replay pen: a PenSource playing recorded samples (evemu, hid-recorder) in real time or at once.
#include "pen/pen_replay.h"


#include <algorithm>
#include <limits>

#include "input/evemu.h"
#include "input/hidrecord.h"

namespace emboss {

ReplayPen::ReplayPen(std::vector<PenSample> samples, std::string name, bool fast, Clock now)
    : samples_(std::move(samples)), name_(std::move(name)), fast_(fast), now_(now ? std::move(now) : Clock(monotonicSeconds)) {
  std::stable_sort(samples_.begin(), samples_.end(), [](const PenSample& a, const PenSample& b) { return a.time_s < b.time_s; });
}

bool ReplayPen::poll(std::vector<PenSample>& out) {
  if (finished()) return true;
  if (fast_) {
    out.insert(out.end(), samples_.begin() + static_cast<std::ptrdiff_t>(next_), samples_.end());
    next_ = samples_.size();
    return true;
  }
  const double now = now_();
  if (!started_) {
    started_ = true;
    start_ = now;
  }
  const double due = samples_.front().time_s + (now - start_);
  while (next_ < samples_.size() && samples_[next_].time_s <= due) out.push_back(samples_[next_++]);
  return true;
}

double ReplayPen::pollWithin() const {
  if (finished()) return std::numeric_limits<double>::infinity();
  if (fast_ || !started_) return 0.0;
  return std::max(0.0, samples_[next_].time_s - samples_.front().time_s - (now_() - start_));
}

Result<std::unique_ptr<PenSource>> openEvemuReplay(const std::filesystem::path& events, bool fast) {
  auto rec = loadEvemu(events);
  if (!rec) return Error{rec.error()};
  auto samples = evemuToSamples(*rec);
  if (!samples) return fail(events.string() + ": " + samples.error());
  if (samples->empty()) return fail(events.string() + " holds no SYN_REPORT frames: nothing to replay");
  const std::string name = "evemu: " + (rec->device.name.empty() ? events.filename().string() : rec->device.name);
  return std::unique_ptr<PenSource>(std::make_unique<ReplayPen>(std::move(*samples), name, fast));
}

Result<std::unique_ptr<PenSource>> openHidRecordReplay(const std::filesystem::path& capture, bool fast) {
  auto rec = loadHidRecord(capture);
  if (!rec) return Error{rec.error()};
  auto samples = decodeHidRecording(*rec);
  if (!samples) return fail(capture.string() + ": " + samples.error());
  if (samples->empty()) return fail(capture.string() + " decodes to no pen samples: nothing to replay");
  const std::string name = "hidrecord: " + (rec->name.empty() ? capture.filename().string() : rec->name);
  return std::unique_ptr<PenSource>(std::make_unique<ReplayPen>(std::move(*samples), name, fast));
}

}  // namespace emboss
