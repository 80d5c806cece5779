// Tests for the replay pen: real-time pacing against a fake clock, fast replay, and the evemu factory.
#include <gtest/gtest.h>

#include <limits>

#include "devices/buttons.h"
#include "pen/pen_replay.h"
#include "test_support.h"

namespace emboss {
namespace {

std::vector<PenSample> timed(std::initializer_list<double> times) {
  std::vector<PenSample> out;
  for (double t : times) {
    PenSample s;
    s.time_s = t;
    s.x = t - 100.0;
    out.push_back(s);
  }
  return out;
}

TEST(ReplayPen, FastHandsOutEverythingAtOnce) {
  ReplayPen pen(timed({100.0, 100.1, 100.25, 101.0}), "test", true, [] { return 0.0; });
  EXPECT_FALSE(pen.finished());
  std::vector<PenSample> out;
  ASSERT_TRUE(pen.poll(out));
  EXPECT_EQ(out.size(), 4u);
  EXPECT_TRUE(pen.finished());
  out.clear();
  ASSERT_TRUE(pen.poll(out));
  EXPECT_TRUE(out.empty());
  EXPECT_EQ(pen.fd(), -1);
  EXPECT_EQ(pen.name(), "test");
}

TEST(ReplayPen, RealTimeFollowsTheClock) {
  double now = 5.0;
  ReplayPen pen(timed({100.0, 100.1, 100.25, 101.0}), "test", false, [&] { return now; });
  std::vector<PenSample> out;
  ASSERT_TRUE(pen.poll(out));  // starts the clock: the first sample is due at once
  ASSERT_EQ(out.size(), 1u);
  EXPECT_DOUBLE_EQ(out[0].time_s, 100.0);  // recorded times are kept
  now = 5.05;
  out.clear();
  pen.poll(out);
  EXPECT_TRUE(out.empty());
  now = 5.1;
  pen.poll(out);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_DOUBLE_EQ(out[0].time_s, 100.1);
  now = 5.9;
  out.clear();
  pen.poll(out);
  ASSERT_EQ(out.size(), 1u);  // 100.25 due, 101.0 not yet
  EXPECT_FALSE(pen.finished());
  EXPECT_EQ(pen.played(), 3u);
  now = 6.0;
  out.clear();
  pen.poll(out);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_TRUE(pen.finished());
}

TEST(ReplayPen, SaysWhenItsNextSampleIsDue) {
  // The kiosk's main loop sleeps that long with nothing else to do: a sample due later than it
  // says would come late, one due sooner would make the loop spin.
  double now = 5.0;
  ReplayPen pen(timed({100.0, 100.1, 100.25, 101.0}), "test", false, [&] { return now; });
  EXPECT_EQ(pen.pollWithin(), 0.0);  // the first poll() starts the clock
  std::vector<PenSample> out;
  pen.poll(out);
  EXPECT_NEAR(pen.pollWithin(), 0.1, 1e-9);
  now = 5.04;
  EXPECT_NEAR(pen.pollWithin(), 0.06, 1e-9);
  now += pen.pollWithin();
  out.clear();
  pen.poll(out);
  ASSERT_EQ(out.size(), 1u);  // due when it said
  EXPECT_DOUBLE_EQ(out[0].time_s, 100.1);
  EXPECT_NEAR(pen.pollWithin(), 0.15, 1e-9);
  now = 5.5;  // polled late: due at once
  EXPECT_EQ(pen.pollWithin(), 0.0);
  pen.poll(out);
  now = 6.0;
  pen.poll(out);
  ASSERT_TRUE(pen.finished());
  EXPECT_EQ(pen.pollWithin(), std::numeric_limits<double>::infinity());

  ReplayPen fast(timed({100.0, 101.0}), "fast", true, [&] { return now; });
  EXPECT_EQ(fast.pollWithin(), 0.0);  // fed as fast as possible: always due
  fast.poll(out);
  EXPECT_EQ(fast.pollWithin(), std::numeric_limits<double>::infinity());
}

TEST(ReplayPen, SourcesSayHowOftenToPollThem) {
  // A source with a descriptor waits for it; one without is polled at the loop's pace.
  QueuedPen queued;
  EXPECT_EQ(queued.fd(), -1);
  EXPECT_EQ(queued.pollWithin(), kPollPaceS);
  QueuedButtons buttons;
  EXPECT_EQ(buttons.pollWithin(), kPollPaceS);
}

TEST(ReplayPen, EmptyRecordingIsFinished) {
  ReplayPen pen({}, "empty", false);
  EXPECT_TRUE(pen.finished());
  std::vector<PenSample> out;
  EXPECT_TRUE(pen.poll(out));
  EXPECT_TRUE(out.empty());
}

TEST(ReplayPen, DefaultClockIsMonotonic) {
  const double a = monotonicSeconds();
  const double b = monotonicSeconds();
  EXPECT_GE(b, a);
  EXPECT_GT(a, 0.0);
}

TEST(ReplayPen, OpensEvemuRecordingsFindingTheirDesc) {
  EMBOSS_REQUIRE_FIXTURES(dir);
  auto pen = openEvemuReplay(dir / "evemu" / "Wacom Intuos4 6x9.stylus-tap.events", true);
  ASSERT_TRUE(pen) << pen.error();
  EXPECT_EQ((*pen)->name(), "evemu: Wacom Intuos4 6x9 Pen");
  std::vector<PenSample> out;
  ASSERT_TRUE((*pen)->poll(out));
  EXPECT_EQ(out.size(), 88u);  // SYN_REPORT lines in the file
  EXPECT_TRUE((*pen)->finished());

  auto slow = openEvemuReplay(dir / "evemu" / "UC-LOGIC Tablet WP5540U Pen.events", false);
  ASSERT_TRUE(slow) << slow.error();
  out.clear();
  (*slow)->poll(out);
  EXPECT_GE(out.size(), 1u);
  EXPECT_FALSE((*slow)->finished());  // a 6-second recording
}

TEST(ReplayPen, OpensHidRecorderCaptures) {
  EMBOSS_REQUIRE_FIXTURES(dir);
  auto pen = openHidRecordReplay(dir / "hid" / "Wacom_PenPartner" / "hidrecord.txt", true);
  ASSERT_TRUE(pen) << pen.error();
  std::vector<PenSample> out;
  (*pen)->poll(out);
  EXPECT_EQ(out.size(), 748u);
}

TEST(ReplayPen, MissingFilesFailClearly) {
  auto pen = openEvemuReplay("/nonexistent/Some Tablet.events", true);
  ASSERT_FALSE(pen);
  EXPECT_NE(pen.error().find("/nonexistent/Some Tablet.events"), std::string::npos) << pen.error();
}

}  // namespace
}  // namespace emboss
