// Stroke-to-screen latency: the figures over every update, and storage that does not grow with them.
#include "app/frame_meter.h"

#include <gtest/gtest.h>

namespace emboss {
namespace {

TEST(LatencyMeter, KeepsFiguresForEveryUpdateButOnlyAWindowOfSamples) {
  LatencyMeter m;
  EXPECT_EQ(m.count(), 0u);
  EXPECT_EQ(m.percentileMs(95), 0.0);
  // Months of strokes: 1, 2, ... ms; the earliest unshown event counts.
  const size_t n = 3 * LatencyMeter::kWindow + 17;
  for (size_t i = 1; i <= n; ++i) {
    m.madeOperation(10.0);
    m.madeOperation(10.5);  // later: the first one is kept
    m.presented(10.0 + double(i) / 1000.0);
  }
  EXPECT_EQ(m.count(), n);
  EXPECT_LE(m.kept(), LatencyMeter::kWindow);
  EXPECT_NEAR(m.meanMs(), (double(n) + 1) / 2, 1e-6);
  EXPECT_NEAR(m.maxMs(), double(n), 1e-6);
  // The percentiles are over the last kWindow updates: n - kWindow + 1 .. n ms.
  EXPECT_NEAR(m.percentileMs(0), double(n - LatencyMeter::kWindow + 1), 1e-6);
  EXPECT_NEAR(m.percentileMs(100), double(n), 1e-6);
  m.presented(99.0);  // nothing pending: nothing counted
  EXPECT_EQ(m.count(), n);
}

TEST(FpsMeter, ThePaceCountsTheTimeBetweenFramesOfAStretchOnly) {
  FpsMeter m;
  m.time(0.5);  // starting up: no frame yet
  for (int i = 0; i < 31; ++i) m.frame(0.5 + i / 30.0);
  m.time(1.0);
  m.pause();  // the mode is left for a minute
  for (int i = 0; i < 16; ++i) m.frame(60.0 + i / 15.0);  // a slower stretch: 15 fps
  m.time(1.0);
  EXPECT_EQ(m.frames(), 47u);
  EXPECT_NEAR(m.meanFps(), 47.0 / 2.5, 1e-9);
  EXPECT_EQ(m.intervals(), 45u);
  EXPECT_NEAR(m.intervalSeconds(), 2.0, 1e-9);
  EXPECT_NEAR(m.paceFps(), 22.5, 1e-9);
  // Without the pause the minute between would count.
  FpsMeter n;
  n.frame(0.0), n.frame(1.0 / 30.0), n.frame(60.0);
  EXPECT_LT(n.paceFps(), 0.1);
}

}  // namespace
}  // namespace emboss
