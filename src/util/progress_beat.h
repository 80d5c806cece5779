// A process-wide count of work done: tiles traced by the thread pool, turns of the kiosk's main loop.
// The service watchdog is fed while it moves (WatchdogFeeder), so a frame that takes longer than
// WatchdogSec on a slow board is not taken for a hang, and a hang (nothing moves) still is.
#pragma once

#include <atomic>
#include <cstdint>

namespace emboss {

inline std::atomic<std::uint64_t>& progressBeats() {
  static std::atomic<std::uint64_t> beats{0};
  return beats;
}
inline void progressBeat() { progressBeats().fetch_add(1, std::memory_order_relaxed); }

// Decides when to tell the watchdog the process is alive: only when work was done since the last
// look, and at most every `interval` seconds (half of WatchdogSec). Not thread-safe: one caller.
class WatchdogFeeder {
 public:
  explicit WatchdogFeeder(double interval) : interval_(interval) {}
  // True when a ping is due now: the beats moved since the last call and `interval` has passed
  // since the last ping.
  bool due(std::uint64_t beats, double now) {
    const bool moved = beats != seen_;
    seen_ = beats;
    moved_ = moved_ || moved;
    if (!moved_ || now - last_ < interval_) return false;
    last_ = now;
    moved_ = false;
    return true;
  }

 private:
  double interval_;
  double last_ = -1e300;
  std::uint64_t seen_ = ~std::uint64_t{0};
  bool moved_ = false;
};

}  // namespace emboss
