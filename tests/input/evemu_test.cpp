// Tests for the evemu parser, the .desc finder, evdev-to-sample conversion and stroke splitting.
#include <gtest/gtest.h>

#include <fstream>

#include "input/evdev_pen_state.h"
#include "input/evemu.h"
#include "test_support.h"

namespace emboss {
namespace {

namespace fs = std::filesystem;

void touch(const fs::path& p, const std::string& text = "") {
  std::ofstream out(p, std::ios::binary);
  out << text;
}

TEST(Evemu, ParsesDescriptionEventsAndComments) {
  const auto rec = parseEvemu(
      "# EVEMU 1.3\n"
      "N: Test Tablet Pen\n"
      "I: 0003 256c 006d 0100\n"
      "B: 01 00 00 00 00 00 00 00 00\n"
      "B: 01 00 00 00 00 00 00 00 00\n"
      "B: 01 00 00 00 00 00 00 00 00\n"
      "B: 01 00 00 00 00 00 00 00 00\n"
      "B: 01 00 00 00 00 00 00 00 00\n"
      "B: 01 01 1c 00 00 00 00 00 00\n"
      "A: 00 0 1000 0 0 10\r\n"
      "A: 01 -10 990 0 0 10\n"
      "A: 18 0 255 0 0\n"
      "E: 0.000000 0001 0140 1\t# EV_KEY / BTN_TOOL_PEN 1\n"
      "E: 0.000010 0003 0000 500\n"
      "E: 0.000010 0003 0001 -10\n"
      "E: 0.000020 0000 0000 0000\n");
  ASSERT_TRUE(rec) << rec.error();
  EXPECT_EQ(rec->device.name, "Test Tablet Pen");
  EXPECT_EQ(rec->device.vendor, 0x256c);
  EXPECT_EQ(rec->device.product, 0x006d);
  ASSERT_EQ(rec->device.axes.size(), 3u);
  EXPECT_EQ(rec->device.axes.at(0x01).min, -10);
  EXPECT_EQ(rec->device.axes.at(0x00).resolution, 10);
  EXPECT_EQ(rec->device.axes.at(0x18).max, 255);
  EXPECT_TRUE(rec->device.hasKey(evcode::kBtnToolPen));
  EXPECT_TRUE(rec->device.hasKey(evcode::kBtnTouch));
  EXPECT_FALSE(rec->device.hasKey(evcode::kBtnToolRubber));
  ASSERT_EQ(rec->events.size(), 4u);
  EXPECT_EQ(rec->events[2].value, -10);
  EXPECT_DOUBLE_EQ(rec->events[3].time_s, 0.00002);

  const auto samples = evemuToSamples(*rec);
  ASSERT_TRUE(samples) << samples.error();
  ASSERT_EQ(samples->size(), 1u);
  EXPECT_DOUBLE_EQ((*samples)[0].x, 0.5);
  EXPECT_DOUBLE_EQ((*samples)[0].y, 0.0);
  EXPECT_TRUE((*samples)[0].inRange);
  EXPECT_FALSE((*samples)[0].tip);
}

TEST(Evemu, MalformedLinesNameTheLine) {
  auto bad = parseEvemu("N: x\nE: 1.0 0003 0000 12\nE: 1.0 zz 0000 12\n");
  ASSERT_FALSE(bad);
  EXPECT_NE(bad.error().find("line 3"), std::string::npos) << bad.error();
  bad = parseEvemu("A: 00 0 notanumber 0 0 0\n");
  ASSERT_FALSE(bad);
  EXPECT_NE(bad.error().find("line 1"), std::string::npos) << bad.error();
  bad = parseEvemu("E: 1.0 0003 0000 99999999999\n");
  EXPECT_FALSE(bad);
}

TEST(Evemu, EventsWithoutDescriptionAskForTheDesc) {
  const auto rec = parseEvemu("E: 0.1 0003 0000 10\nE: 0.1 0000 0000 0\n");
  ASSERT_TRUE(rec);
  const auto samples = evemuToSamples(*rec);
  ASSERT_FALSE(samples);
  EXPECT_NE(samples.error().find(".desc"), std::string::npos) << samples.error();
}

TEST(Evemu, FindDescRule) {
  const fs::path dir = test::scratchDir("evemu_find_desc");
  touch(dir / "Acme Slate 5 Pen.desc");
  touch(dir / "Acme Slate 5 Finger.desc");
  touch(dir / "Acme.desc");
  touch(dir / "Other Tablet.desc");
  touch(dir / "Acme Slate 5.session-2.events");
  touch(dir / "Other Tablet.events");
  touch(dir / "Unrelated thing.events");

  // The longest word-prefix wins; between "Pen" and "Finger" interfaces the pen.
  auto d = findEvemuDesc(dir / "Acme Slate 5.session-2.events");
  ASSERT_TRUE(d) << d.error();
  EXPECT_EQ(d->filename(), "Acme Slate 5 Pen.desc");
  // Same stem wins outright.
  d = findEvemuDesc(dir / "Other Tablet.events");
  ASSERT_TRUE(d) << d.error();
  EXPECT_EQ(d->filename(), "Other Tablet.desc");
  // Nothing matches: the message lists what it saw and suggests --desc.
  d = findEvemuDesc(dir / "Unrelated thing.events");
  ASSERT_FALSE(d);
  EXPECT_NE(d.error().find("--desc"), std::string::npos) << d.error();
  EXPECT_NE(d.error().find("Acme Slate 5 Pen.desc"), std::string::npos) << d.error();
  // "Acme Slate 50" must not match "Acme Slate 5 Pen": whole words only.
  touch(dir / "Acme Slate 50.x.events");
  d = findEvemuDesc(dir / "Acme Slate 50.x.events");
  ASSERT_TRUE(d) << d.error();
  EXPECT_EQ(d->filename(), "Acme.desc");
}

TEST(Evemu, FindDescOnTheRealRecordings) {
  EMBOSS_REQUIRE_FIXTURES(dir);
  for (const char* f : {"Wacom Intuos4 6x9.stylus-tap.events", "Wacom Intuos4 6x9.stylus-drag.events",
                        "Wacom Intuos4 6x9.stylus-move.events"}) {
    const auto d = findEvemuDesc(dir / "evemu" / f);
    ASSERT_TRUE(d) << f << ": " << d.error();
    EXPECT_EQ(d->filename(), "Wacom Intuos4 6x9 Pen.desc") << f;
  }
  const auto g = findEvemuDesc(dir / "evemu" / "Genius EasyPen i405X.events");
  ASSERT_TRUE(g) << g.error();
  EXPECT_EQ(g->filename(), "Genius EasyPen i405X.desc");
}

// Expected figures counted by hand from the .events files with awk:
//   frames      = SYN_REPORT lines:     awk '$1=="E:" && $3=="0000" && $4=="0000"' | wc -l
//   strokes     = BTN_TOUCH presses:    awk '$1=="E:" && $3=="0001" && $4=="014a" && $5+0==1' | wc -l
//   tip frames  = SYN_REPORTs seen while the last BTN_TOUCH value was 1
//   maxPressure = largest ABS_PRESSURE (0018) value, over the device's axis max from the A: line
//                 (UC-LOGIC: 451 of 1023; Intuos4: 2047 of 2047; the others send no pressure).
struct RecordingFigures {
  const char* file;
  size_t frames;
  size_t strokes;
  size_t tipFrames;
  double maxPressure;
};

class EvemuRecordings : public ::testing::TestWithParam<RecordingFigures> {};

TEST_P(EvemuRecordings, DecodeToTheCountedStrokes) {
  EMBOSS_REQUIRE_FIXTURES(dir);
  const auto& fig = GetParam();
  const auto rec = loadEvemu(dir / "evemu" / fig.file);
  ASSERT_TRUE(rec) << rec.error();
  const auto samples = evemuToSamples(*rec);
  ASSERT_TRUE(samples) << samples.error();
  EXPECT_EQ(samples->size(), fig.frames);
  size_t tips = 0;
  double maxP = 0.0;
  for (const auto& s : *samples) {
    ASSERT_GE(s.x, 0.0);
    ASSERT_LE(s.x, 1.0);
    ASSERT_GE(s.y, 0.0);
    ASSERT_LE(s.y, 1.0);
    ASSERT_GE(s.pressure, 0.0);
    ASSERT_LE(s.pressure, 1.0);
    if (s.tip) {
      EXPECT_TRUE(s.inRange);
    }
    tips += s.tip;
    maxP = std::max(maxP, s.pressure);
  }
  EXPECT_EQ(tips, fig.tipFrames);
  EXPECT_NEAR(maxP, fig.maxPressure, 1e-9);
  const auto strokes = splitStrokes(*samples);
  ASSERT_EQ(strokes.size(), fig.strokes);
  for (const auto& st : strokes) {
    // Pressure rises from the first contact and falls before the lift.
    double peak = 0.0;
    for (const auto& s : st) peak = std::max(peak, s.pressure);
    EXPECT_LT(st.front().pressure, peak);
    EXPECT_LT(st.back().pressure, peak);
    for (size_t i = 1; i < st.size(); ++i) EXPECT_GE(st[i].time_s, st[i - 1].time_s);
  }
}

INSTANTIATE_TEST_SUITE_P(
    Fixtures, EvemuRecordings,
    ::testing::Values(RecordingFigures{"Genius EasyPen i405X.events", 1112, 0, 0, 0.0},
                      RecordingFigures{"UC-LOGIC Tablet WP5540U Pen.events", 506, 1, 459, 451.0 / 1023.0},
                      RecordingFigures{"Wacom Intuos4 6x9.stylus-drag.events", 361, 1, 295, 1.0},
                      RecordingFigures{"Wacom Intuos4 6x9.stylus-move.events", 444, 0, 0, 0.0},
                      RecordingFigures{"Wacom Intuos4 6x9.stylus-tap.events", 88, 1, 53, 1.0}));

TEST(Evemu, ProximityFollowsTheToolKey) {
  EMBOSS_REQUIRE_FIXTURES(dir);
  // Genius: BTN_TOOL_PEN 1 first, BTN_TOOL_PEN 0 before the last frame (grep 0140).
  const auto rec = loadEvemu(dir / "evemu" / "Genius EasyPen i405X.events");
  ASSERT_TRUE(rec) << rec.error();
  const auto samples = evemuToSamples(*rec);
  ASSERT_TRUE(samples);
  EXPECT_TRUE(samples->front().inRange);
  EXPECT_FALSE(samples->back().inRange);
  // UC-LOGIC has no tool keys: in range from its first position on.
  const auto uc = loadEvemu(dir / "evemu" / "UC-LOGIC Tablet WP5540U Pen.events");
  ASSERT_TRUE(uc) << uc.error();
  const auto us = evemuToSamples(*uc);
  ASSERT_TRUE(us);
  for (const auto& s : *us) EXPECT_TRUE(s.inRange);
}

TEST(EvdevPenState, DropsEventsUpToTheNextReportAfterSynDropped) {
  EvdevPenState st({{evcode::kAbsX, {0, 100}}, {evcode::kAbsY, {0, 100}}, {evcode::kAbsPressure, {0, 10}}}, true, true);
  st.feed(0, evcode::kEvKey, evcode::kBtnToolPen, 1);
  st.feed(0, evcode::kEvAbs, evcode::kAbsX, 50);
  ASSERT_TRUE(st.feed(0, evcode::kEvSyn, evcode::kSynReport, 0));
  st.feed(1, evcode::kEvSyn, evcode::kSynDropped, 0);
  st.feed(1, evcode::kEvAbs, evcode::kAbsX, 90);
  EXPECT_FALSE(st.feed(1, evcode::kEvSyn, evcode::kSynReport, 0));
  st.feed(2, evcode::kEvAbs, evcode::kAbsY, 25);
  st.feed(2, evcode::kEvAbs, evcode::kAbsPressure, 5);
  st.feed(2, evcode::kEvKey, evcode::kBtnTouch, 1);
  st.feed(2, evcode::kEvKey, evcode::kBtnStylus2, 1);
  const auto s = st.feed(2, evcode::kEvSyn, evcode::kSynReport, 0);
  ASSERT_TRUE(s);
  EXPECT_DOUBLE_EQ(s->x, 0.5);  // the dropped 90 never applied
  EXPECT_DOUBLE_EQ(s->y, 0.25);
  EXPECT_DOUBLE_EQ(s->pressure, 0.5);
  EXPECT_TRUE(s->tip);
  EXPECT_TRUE(s->barrel2);
  EXPECT_FALSE(s->barrel1);
}

TEST(EvdevPenState, WithoutTouchKeyTheTipIsPressure) {
  EvdevPenState st({{evcode::kAbsX, {0, 100}}, {evcode::kAbsY, {0, 100}}, {evcode::kAbsPressure, {0, 10}}}, false, false);
  st.feed(0, evcode::kEvAbs, evcode::kAbsPressure, 3);
  const auto s = st.feed(0, evcode::kEvSyn, evcode::kSynReport, 0);
  ASSERT_TRUE(s);
  EXPECT_TRUE(s->tip);
  EXPECT_TRUE(s->inRange);
}

TEST(EvdevPenState, UnusableReasons) {
  EvdevCaps mouse;
  EXPECT_TRUE(evdevUnusableReason(mouse));
  EvdevCaps pad;
  pad.abs[evcode::kAbsX] = {0, 1000};
  pad.abs[evcode::kAbsY] = {0, 1000};
  pad.hasToolFinger = true;
  pad.hasTouch = true;
  ASSERT_TRUE(evdevUnusableReason(pad));
  EXPECT_NE(evdevUnusableReason(pad)->find("touch"), std::string::npos);
  EvdevCaps pen = pad;
  pen.hasToolFinger = false;
  pen.hasToolPen = true;
  EXPECT_FALSE(evdevUnusableReason(pen));
  EvdevCaps empty = pen;
  empty.abs[evcode::kAbsX] = {0, 0};
  EXPECT_TRUE(evdevUnusableReason(empty));
  EvdevCaps uclogic;  // the WP5540U: no tool keys, BTN_STYLUS and pressure
  uclogic.abs = pen.abs;
  uclogic.abs[evcode::kAbsPressure] = {0, 1023};
  uclogic.hasTouch = uclogic.hasStylus = true;
  EXPECT_FALSE(evdevUnusableReason(uclogic));
}

TEST(Strokes, SplitAtTipChanges) {
  std::vector<PenSample> s(7);
  const bool tips[] = {false, true, true, false, true, false, true};
  for (size_t i = 0; i < s.size(); ++i) s[i].tip = tips[i];
  const auto strokes = splitStrokes(s);
  ASSERT_EQ(strokes.size(), 3u);
  EXPECT_EQ(strokes[0].size(), 2u);
  EXPECT_EQ(strokes[1].size(), 1u);
  EXPECT_EQ(strokes[2].size(), 1u);
}

}  // namespace
}  // namespace emboss
