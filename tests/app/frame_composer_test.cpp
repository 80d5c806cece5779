// The kiosk's scheduling of the ray tracer: whatever the order of dirty rectangles, previews and
// refinement bands, the finished frame equals one full render.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstring>

#include <cstdlib>

#include "app/frame_composer.h"
#include "app/view_orbit.h"
#include "app/workbench.h"
#include "frep/workpieces.h"

namespace emboss {
namespace {

constexpr int kW = 200, kH = 125;

Image fullRender(ThreadPool& pool, const Model& m, const CameraSpec& c, const ShadingParams& s, int w = kW, int h = kH) {
  Renderer r(pool);
  r.sync(m);
  r.setCamera(Camera(c, w, h));
  r.setShading(s);
  Image img;
  r.renderFull(img);
  return img;
}

// The shading of a bare 0.5 mm sheet of the named metal.
ShadingParams sheetOf(const char* metal) {
  ShadingParams sh;
  sh.metal = *metalByName(metal);
  sh.tinge = tinges()[0];
  sh.frontZ = 0.5;
  return sh;
}

Operation punch(double x, double y) {
  Operation op;
  op.kind = OpKind::Punch;
  op.a = 3, op.p = 0.25, op.q = 1;
  op.at = {x, y, 0.5};
  return op;
}

// A region raised from behind: the rectangle of half sides hx, hy round the sheet's centre.
Operation raisedRectangle(double hx, double hy) {
  Operation op;
  op.kind = OpKind::Region;
  op.side = Side::Back;
  op.points = {{-hx, -hy}, {hx, -hy}, {hx, hy}, {-hx, hy}};
  op.height = 0.8;
  op.falloff = 2.0;
  return op;
}

Operation sphereOn(double x, double y) {
  Operation op;
  op.kind = OpKind::BlendUnion;
  op.tool.type = ToolShape::Type::Sphere;
  op.tool.center = {x, y, 0.5};
  op.tool.r = 2.0;
  op.a1 = 0.5, op.a2 = 1.0, op.a3 = 1.0;
  return op;
}

// A model cleared while another is shown (the bench when a visitor leaves and attract mode plays):
// release() lets its renderer give back what it held for the piece (index lists, set operations'
// fields); without it they stay until the bench is shown again.
TEST(FrameComposer, ReleaseGivesBackWhatAClearedModelHeld) {
  ThreadPool pool(2);
  FrameComposer fc(pool, kW, kH);
  Model bench(std::make_shared<Plate>(60.0, 40.0, 0.5), Deformation::Sheet);
  Model attract(std::make_shared<Plate>(60.0, 40.0, 0.5), Deformation::Sheet);
  const CameraSpec home = benchCamera(bench.workpiece().bounds(), kW, kH);
  const ShadingParams sh = sheetOf("copper");
  std::vector<Rect> changed;
  fc.show(bench, home, sh, {true, false, {}}, false);
  fc.flush(changed);
  const size_t blank = fc.memoryBytes();
  for (int i = 0; i < 40; ++i) {
    ASSERT_TRUE(bench.add(punch(-25 + 1.2 * i, -10 + 0.5 * i)));
    if (i % 8 == 0) {
      ASSERT_TRUE(bench.add(sphereOn(-20 + i, 5)));
    }
  }
  fc.show(bench, home, sh, {true, false, {}}, false);
  fc.flush(changed);
  const size_t worked = fc.memoryBytes();
  ASSERT_GT(worked, blank + 1000000) << "five set operations' fields and the index";
  fc.show(attract, home, sh, {true, false, {}}, false);  // attract mode plays
  fc.flush(changed);
  const size_t both = fc.memoryBytes();
  bench.clear();  // the visitor left
  EXPECT_EQ(fc.memoryBytes(), both) << "nothing is given back until the renderer catches up";
  fc.release(bench);
  // What is left: two blank sheets' fields and indexes.
  EXPECT_LT(fc.memoryBytes(), both - (worked - blank) + 4096);
  EXPECT_LE(fc.memoryBytes(), 2 * blank + 4096);
  // The bench shown again (the next visitor) is rendered as a full render would.
  ASSERT_TRUE(bench.add(punch(0, 0)));
  fc.show(bench, home, sh, {true, false, {}}, false);
  fc.flush(changed);
  EXPECT_EQ(fc.frame().rgba, fullRender(pool, bench, home, sh).rgba);
}

TEST(FrameComposer, FinishedFrameEqualsAFullRender) {
  ThreadPool pool(2);
  FrameComposer fc(pool, kW, kH);
  Model m(std::make_shared<Plate>(60.0, 40.0, 0.5), Deformation::Sheet);
  const CameraSpec home = benchCamera(m.workpiece().bounds(), kW, kH);
  const ShadingParams sh = sheetOf("copper");
  std::vector<Rect> changed;
  fc.show(m, home, sh, {true, false, {}}, false);
  fc.work(1.0, changed);  // a preview and a band or two: not finished
  EXPECT_TRUE(fc.refining());
  // Operations arrive while the refinement is under way.
  for (int i = 0; i < 5; ++i) {
    ASSERT_TRUE(m.add(punch(-20 + 10 * i, 5)));
    fc.show(m, home, sh, {false, false, {m.activeCount() - 1}}, false);
    fc.work(2.0, changed);
  }
  m.undo();
  fc.show(m, home, sh, {false, false, {m.activeCount()}}, false);
  std::vector<Rect> all;
  fc.flush(all);
  EXPECT_FALSE(fc.pending());
  EXPECT_EQ(fc.frame().rgba, fullRender(pool, m, home, sh).rgba);

  // The camera moves (previews only), then stops: refined to the exact frame again.
  Orbit o = orbitOf(home);
  for (int i = 1; i <= 3; ++i) {
    o.azimuthDeg = -8.0 * i;
    fc.show(m, cameraAt(o, home), sh, {false, true, {}}, true);
    fc.work(5.0, changed);
    EXPECT_FALSE(fc.refining());
  }
  const CameraSpec turned = cameraAt(o, home);
  fc.show(m, turned, sh, {false, true, {}}, false);
  fc.flush(all);
  EXPECT_EQ(fc.frame().rgba, fullRender(pool, m, turned, sh).rgba);
  EXPECT_GT(fc.counters().previews, 3u);

  // Back to a bare sheet of the first view: the remembered picture, exact.
  Model bare(m.workpiecePtr(), Deformation::Sheet);
  Model bare2(m.workpiecePtr(), Deformation::Sheet);
  fc.show(bare, home, sh, {true, false, {}}, false);
  fc.flush(all);
  fc.show(bare2, home, sh, {true, false, {}}, false);
  const auto reused = fc.counters().blankReuses;
  fc.flush(all);
  EXPECT_EQ(reused, 1u);
  EXPECT_EQ(fc.frame().rgba, fullRender(pool, bare2, home, sh).rgba);
}

// flush() with a limit (the kiosk's last frame on SIGTERM: systemd waits 15 s) stops between bands
// with the frame still pending, and the rest is traced by the next flush, to the exact frame.
TEST(FrameComposer, AFlushWithALimitStopsAndTheNextOneFinishes) {
  ThreadPool pool(2);
  FrameComposer fc(pool, kW, kH);
  Model m(std::make_shared<Plate>(60.0, 40.0, 0.5), Deformation::Sheet);
  for (int i = 0; i < 6; ++i) ASSERT_TRUE(m.add(punch(-20 + 8 * i, 3)));
  const CameraSpec home = benchCamera(m.workpiece().bounds(), kW, kH);
  const ShadingParams sh = sheetOf("copper");
  std::vector<Rect> changed;
  fc.show(m, home, sh, {true, false, {}}, false);
  EXPECT_FALSE(fc.flush(changed, 0.0)) << "no time at all: nothing finished";
  EXPECT_TRUE(fc.pending());
  fc.work(0.5, changed);  // a preview and a band: under way
  EXPECT_TRUE(fc.refining());
  EXPECT_FALSE(fc.flush(changed, 0.0));
  EXPECT_TRUE(fc.refining());
  EXPECT_TRUE(fc.flush(changed, 60000.0));
  EXPECT_FALSE(fc.pending());
  EXPECT_EQ(fc.frame().rgba, fullRender(pool, m, home, sh).rgba);
}

// A 480 x 300 composer over the bare 60 x 40 mm copper plate, its first frame finished.
struct PlateOnScreen {
  static constexpr int w = 480, h = 300;
  ThreadPool pool{2};
  FrameComposer fc{pool, w, h};
  Model m{std::make_shared<Plate>(60.0, 40.0, 0.5), Deformation::Sheet};
  CameraSpec home = benchCamera(m.workpiece().bounds(), w, h);
  ShadingParams sh = sheetOf("copper");
  // `traced`: the first frame finished (its bands measure the tracing speed), else only shown.
  explicit PlateOnScreen(bool traced = true) {
    std::vector<Rect> changed;
    fc.show(m, home, sh, {true, false, {}}, false);
    if (traced) fc.flush(changed);
  }
};

// A dirty rectangle too big to trace within the frame (a raised region close up) is shown coarse
// at once, the call returning so the kiosk presents it; its exact pixels follow in the next calls,
// and the finished frame is a full render's, byte for byte.
TEST(FrameComposer, ABigDirtyRectangleIsShownCoarseThenExact) {
  PlateOnScreen t;
  auto& [pool, fc, m, home, sh] = t;
  constexpr int w = PlateOnScreen::w, h = PlateOnScreen::h;
  std::vector<Rect> changed;
  // What may be traced at once: a twentieth of a millisecond, so that the region is too big on
  // any machine.
  fc.setDirtyBudget(0.05);
  fc.setFieldBandMs(0);  // (its field at once; see ABigRegionRisesABandOfRowsATurnToTheExactFrame)
  fc.setPreviewScale(3);  // (the scale a busy machine's slow preview would have raised)
  const Image before = fc.frame();
  ASSERT_TRUE(m.add(raisedRectangle(18, 12)));
  fc.show(m, home, sh, {false, false, {m.activeCount() - 1}}, false);
  changed.clear();
  fc.work(1000.0, changed, true);
  EXPECT_EQ(fc.counters().coarseRects, 1u);
  EXPECT_TRUE(fc.pending()) << "the exact pixels are still to come";
  ASSERT_EQ(changed.size(), 1u);
  const Rect r = changed[0];
  EXPECT_GT(r.area(), w * h / 10);
  // The coarse picture shows the region: it differs from the frame before in most of the
  // rectangle, and from the exact one by little.
  const Image coarse = fc.frame();
  std::vector<Rect> rest;
  fc.flush(rest);
  EXPECT_FALSE(fc.pending());
  const Image exact = fullRender(pool, m, home, sh, w, h);
  EXPECT_EQ(fc.frame().rgba, exact.rgba);
  long moved = 0, far = 0;
  for (int y = r.y; y < r.y + r.h; ++y)
    for (int x = r.x; x < r.x + r.w; ++x)
      for (int k = 0; k < 3; ++k) {
        moved += coarse.pixel(x, y)[k] != before.pixel(x, y)[k];
        far += std::abs(coarse.pixel(x, y)[k] - exact.pixel(x, y)[k]) > 24;
      }
  EXPECT_GT(moved, r.area());          // over a third of the channels changed
  EXPECT_LT(far, r.area() * 3 / 20);   // at most 5 % of them far from the exact picture
  // Within the budget a stroke is traced exactly at once.
  fc.setDirtyBudget(1e6);
  ASSERT_TRUE(m.add(punch(0, 0)));
  fc.show(m, home, sh, {false, false, {m.activeCount() - 1}}, false);
  fc.work(1000.0, changed, true);
  EXPECT_EQ(fc.counters().coarseRects, 1u);
  EXPECT_FALSE(fc.pending());
  EXPECT_EQ(fc.frame().rgba, fullRender(pool, m, home, sh, w, h).rgba);
}

// A dirty rectangle traced exactly (its cost not known beforehand: a small rectangle over a pile
// of set operations) stops once it has taken more than its share of the dirty budget, and is shown
// coarse instead; the finished frame is a full render's, byte for byte.
TEST(FrameComposer, ADirtyRectangleThatOverrunsTheBudgetIsShownCoarseThenExact) {
  PlateOnScreen t(false);
  auto& [pool, fc, m, home, sh] = t;
  std::vector<Rect> changed;
  // Nothing traced yet, so no speed is known and the stroke is traced exactly; a nanosecond's
  // budget is overrun by anything.
  fc.setDirtyBudget(1e-6);
  ASSERT_TRUE(m.add(punch(0, 0)));
  fc.show(m, home, sh, {false, false, {m.activeCount() - 1}}, false);
  fc.work(1000.0, changed, true);
  EXPECT_EQ(fc.counters().dirtyStopped, 1u);
  EXPECT_EQ(fc.counters().coarseRects, 1u);
  EXPECT_TRUE(fc.pending()) << "the exact pixels are still to come";
  fc.flush(changed);
  EXPECT_FALSE(fc.pending());
  EXPECT_EQ(fc.frame().rgba, fullRender(pool, m, home, sh, PlateOnScreen::w, PlateOnScreen::h).rgba);
}

// Where coarse pictures cost more than the dirty budget (rays through a pile of set operations),
// the next is coarser still: traced from fewer rays, and the finished frame is a full render's.
TEST(FrameComposer, ACoarsePictureGoesCoarserWhereTheLastOneCostTooMuch) {
  PlateOnScreen t;
  auto& [pool, fc, m, home, sh] = t;
  constexpr int w = PlateOnScreen::w, h = PlateOnScreen::h;
  std::vector<Rect> changed;
  // Ten microseconds, the least dirty budget too: any coarse picture costs far more than this.
  // (With the least dirty budget at its default, 1 ms, a picture at scale 15 cost less than that
  // once rays walked in SIMD lanes, and the second picture stopped at 15 on a quiet machine.)
  fc.setDirtyBudget(0.01);
  fc.setFieldBandMs(0);
  // (none stops at its budget: its scale is the one the last picture's cost chose)
  fc.setLeastBudgets(0.01, 1e9);
  const auto coarseRays = [&](const Operation& op) {
    const std::uint64_t before = fc.counters().render.rays, coarseBefore = fc.counters().coarseRects;
    EXPECT_TRUE(m.add(op));
    fc.show(m, home, sh, {false, false, {m.activeCount() - 1}}, false);
    changed.clear();
    fc.work(1000.0, changed, true);
    EXPECT_EQ(fc.counters().coarseRects, coarseBefore + 1);
    const std::uint64_t rays = fc.counters().render.rays - before;
    fc.flush(changed);
    return rays;
  };
  // The first at the preview's scale (8 at most), the second at 16.
  const std::uint64_t first = coarseRays(raisedRectangle(18, 12)), second = coarseRays(raisedRectangle(17, 11));
  EXPECT_GT(second, 0u);
  EXPECT_LT(3 * second, first) << "the second coarse picture was not coarser";
  EXPECT_EQ(fc.lastCoarseScale(), FrameComposer::kMaxCoarseScale);
  EXPECT_EQ(fc.counters().coarseStopped, 0u);
  EXPECT_EQ(fc.frame().rgba, fullRender(pool, m, home, sh, w, h).rgba);
}

// A coarse picture that costs more than its budget (its rays dearer than the last pictures' were:
// a pile of set operations grown under the pen) stops there, and the coarsest picture is shown
// instead; the finished frame is a full render's. Stopped before its first ray (its time spent
// before the tracing), it says nothing of what a ray costs: the next coarse picture is traced at
// the preview's scale as before, not made as coarse as it goes (that wait had counted as one
// ray's cost).
TEST(FrameComposer, ACoarsePictureThatOverrunsItsBudgetShowsTheCoarsest) {
  PlateOnScreen t;
  auto& [pool, fc, m, home, sh] = t;
  constexpr int w = PlateOnScreen::w, h = PlateOnScreen::h;
  std::vector<Rect> changed;
  fc.setDirtyBudget(0.05);        // the region is shown coarse
  fc.setLeastBudgets(1.0, 1e-6);  // and its coarse picture overruns a nanosecond
  fc.setFieldBandMs(0);
  const Image before = fc.frame();
  ASSERT_TRUE(m.add(raisedRectangle(18, 12)));
  fc.show(m, home, sh, {false, false, {m.activeCount() - 1}}, false);
  fc.work(1000.0, changed, true);
  EXPECT_EQ(fc.counters().coarseRects, 1u);
  EXPECT_EQ(fc.counters().coarseStopped, 1u);
  EXPECT_EQ(fc.lastCoarseScale(), FrameComposer::kMaxCoarseScale);
  ASSERT_EQ(changed.size(), 1u);
  // The coarsest picture shows the region all the same: most of its pixels changed.
  const Rect r = changed[0];
  long moved = 0;
  for (int y = r.y; y < r.y + r.h; ++y)
    for (int x = r.x; x < r.x + r.w; ++x) moved += std::memcmp(fc.frame().pixel(x, y), before.pixel(x, y), 3) != 0;
  EXPECT_GT(moved, r.area() / 2);
  EXPECT_TRUE(fc.pending());
  fc.flush(changed);
  EXPECT_EQ(fc.frame().rgba, fullRender(pool, m, home, sh, w, h).rgba);
  // (a nanosecond: it stopped before its first ray) The next, never stopped.
  fc.setLeastBudgets(1.0, 1e9);
  ASSERT_TRUE(m.add(raisedRectangle(17, 11)));
  fc.show(m, home, sh, {false, false, {m.activeCount() - 1}}, false);
  fc.work(1000.0, changed, true);
  EXPECT_EQ(fc.counters().coarseRects, 2u);
  EXPECT_EQ(fc.counters().coarseStopped, 1u);
  EXPECT_EQ(fc.lastCoarseScale(), fc.previewScale());
  EXPECT_LT(fc.lastCoarseScale(), FrameComposer::kMaxCoarseScale);
  fc.flush(changed);
  EXPECT_EQ(fc.frame().rgba, fullRender(pool, m, home, sh, w, h).rgba);
}

// A visitor's step that spent its frame before the tracing (a raised region's field over a pile
// of set operations) leaves the dirty rectangles less than their budget: work()'s presentBy. Past
// it, a stroke that would be traced exactly within the budget is shown coarse.
TEST(FrameComposer, WhatTheStepSpentComesOffTheDirtyBudget) {
  PlateOnScreen t(false);
  auto& [pool, fc, m, home, sh] = t;
  std::vector<Rect> changed;
  fc.setDirtyBudget(1e6);          // a stroke alone is always traced exactly
  fc.setLeastBudgets(1e-6, 1e9);   // a step past its time leaves it a nanosecond
  const auto now = std::chrono::steady_clock::now();
  ASSERT_TRUE(m.add(punch(-10, 0)));
  fc.show(m, home, sh, {false, false, {m.activeCount() - 1}}, false);
  fc.work(1000.0, changed, true, false, now + std::chrono::hours(1));
  EXPECT_EQ(fc.counters().dirtyStopped, 0u);
  EXPECT_EQ(fc.counters().coarseRects, 0u);
  ASSERT_TRUE(m.add(punch(10, 0)));
  fc.show(m, home, sh, {false, false, {m.activeCount() - 1}}, false);
  fc.work(1000.0, changed, true, false, now - std::chrono::milliseconds(20));
  // (traced coarse at once where the first punch measured the speed, else stopped: either way
  // shown coarse)
  EXPECT_EQ(fc.counters().coarseRects, 1u);
  EXPECT_TRUE(fc.pending());
  EXPECT_EQ(fc.counters().coarseStopped, 0u);
  fc.flush(changed);
  EXPECT_EQ(fc.frame().rgba, fullRender(pool, m, home, sh, PlateOnScreen::w, PlateOnScreen::h).rgba);
}

// Attract mode presents on a fixed grid of ticks: a stroke's dirty rectangles traced late in a
// period made the next tick late (a rectangle's cost is not known beforehand), so with `mayWait`
// they wait for a call with at least kWaitUnlessMs of budget, the start of a period.
TEST(FrameComposer, InAttractModeAStrokeWaitsForTheStartOfAPeriod) {
  ThreadPool pool(2);
  FrameComposer fc(pool, kW, kH);
  // Every stroke traced exactly, however busy the machine: with the usual 6 ms, a punch's trace
  // held up by other processes was stopped and shown coarse, and the frames below were not yet a
  // full render's (the test failed once in a test run beside other heavy jobs).
  fc.setDirtyBudget(1e6);
  Model m(std::make_shared<Plate>(60.0, 40.0, 0.5), Deformation::Sheet);
  const CameraSpec home = benchCamera(m.workpiece().bounds(), kW, kH);
  const ShadingParams sh = sheetOf("copper");
  std::vector<Rect> changed;
  fc.show(m, home, sh, {true, false, {}}, false);
  fc.flush(changed);
  ASSERT_TRUE(m.add(punch(0, 0)));
  fc.show(m, home, sh, {false, false, {m.activeCount() - 1}}, false);
  const Image before = fc.frame();
  // Late in a period: nothing traced, the stroke still to come.
  changed.clear();
  fc.work(FrameComposer::kWaitUnlessMs - 5.0, changed, false, true);
  EXPECT_TRUE(changed.empty());
  EXPECT_EQ(fc.counters().dirtyWaits, 1u);
  EXPECT_EQ(fc.frame().rgba, before.rgba);
  EXPECT_TRUE(fc.pending());
  // At the start of the next: traced, and the frame is a full render's.
  fc.work(FrameComposer::kWaitUnlessMs + 10.0, changed, false, true);
  EXPECT_FALSE(changed.empty());
  EXPECT_EQ(fc.counters().dirtyWaits, 1u);
  EXPECT_EQ(fc.counters().dirtyStopped, 0u);
  EXPECT_EQ(fc.frame().rgba, fullRender(pool, m, home, sh).rgba);
  // A visitor's stroke never waits, whatever is left of the budget.
  ASSERT_TRUE(m.add(punch(8, 4)));
  fc.show(m, home, sh, {false, false, {m.activeCount() - 1}}, false);
  changed.clear();
  fc.work(2.0, changed, true);
  EXPECT_FALSE(changed.empty());
  EXPECT_EQ(fc.counters().dirtyWaits, 1u);
  EXPECT_EQ(fc.frame().rgba, fullRender(pool, m, home, sh).rgba);
}

// A raised region over most of the sheet rises a band of rows a turn (its field work cut to
// FrameComposer::kFieldBandMs a turn; here to eight rows): the first turn shows its first
// rows, and the finished frame is a full render's. A punch made while it rises, and
// the region undone while it rises, end the same way.
TEST(FrameComposer, ABigRegionRisesABandOfRowsATurnToTheExactFrame) {
  constexpr int w = 320, h = 200;
  ThreadPool pool(2);
  FrameComposer fc(pool, w, h);
  Model m(std::make_shared<Plate>(60.0, 40.0, 0.5), Deformation::Sheet);
  const CameraSpec home = benchCamera(m.workpiece().bounds(), w, h);
  const ShadingParams sh = sheetOf("copper");
  fc.setFieldBandMs(0.001);  // eight rows a turn, on any machine
  std::vector<Rect> changed;
  fc.show(m, home, sh, {true, false, {}}, false);
  fc.flush(changed);
  const Operation region = raisedRectangle(26, 17);
  auto raise = [&] {
    EXPECT_TRUE(m.add(region));
    fc.show(m, home, sh, {false, false, {m.activeCount() - 1}}, false);
    fc.work(1000.0, changed, true);
  };
  raise();
  const Image first = fc.frame();
  int turns = 1;
  for (; fc.pending() && turns < 1000; ++turns) fc.work(1000.0, changed, true);
  EXPECT_FALSE(fc.pending());
  EXPECT_GE(fc.counters().fieldBands, 4u);
  EXPECT_GE(turns, 5);
  const Image exact = fullRender(pool, m, home, sh, w, h);
  EXPECT_EQ(fc.frame().rgba, exact.rgba);
  EXPECT_NE(first.rgba, exact.rgba) << "the first turn shows the region's first rows only";

  // A punch while it rises (its other rows are added first), then the finished frame.
  m.undo();
  fc.show(m, home, sh, {false, false, {m.activeCount()}}, false);
  fc.flush(changed);
  raise();
  ASSERT_TRUE(fc.pending());
  ASSERT_TRUE(m.add(punch(5, 3)));
  fc.show(m, home, sh, {false, false, {m.activeCount() - 1}}, false);
  fc.flush(changed);
  EXPECT_EQ(fc.frame().rgba, fullRender(pool, m, home, sh, w, h).rgba);

  // Undone while it rises.
  raise();
  ASSERT_TRUE(fc.pending());
  m.undo();
  fc.show(m, home, sh, {false, false, {m.activeCount()}}, false);
  fc.flush(changed);
  EXPECT_EQ(fc.frame().rgba, fullRender(pool, m, home, sh, w, h).rgba);
}

TEST(FrameComposer, GoingBackAndForthBetweenTwoModelsRebuildsNoField) {
  ThreadPool pool(2);
  FrameComposer fc(pool, kW, kH);
  auto plate = std::make_shared<Plate>(60.0, 40.0, 0.5);
  Model piece(plate, Deformation::Sheet), bench(std::make_shared<Plate>(60.0, 40.0, 0.5), Deformation::Sheet);
  for (int i = 0; i < 4; ++i) ASSERT_TRUE(piece.add(punch(-15 + 10 * i, -5)));
  const CameraSpec home = benchCamera(plate->bounds(), kW, kH);
  const ShadingParams sh = sheetOf("brass");
  std::vector<Rect> all;
  fc.show(piece, home, sh, {true, false, {}}, false);
  fc.flush(all);
  fc.show(bench, home, sh, {true, false, {}}, false);
  fc.flush(all);
  EXPECT_EQ(fc.counters().fieldRebuilds, 2u);
  // Each changes while the other is shown; switching back follows the change, no rebuild.
  for (int round = 0; round < 3; ++round) {
    ASSERT_TRUE(piece.add(punch(-10 + 5 * round, 8)));
    fc.show(piece, home, sh, {true, false, {}}, false);
    fc.flush(all);
    EXPECT_EQ(fc.frame().rgba, fullRender(pool, piece, home, sh).rgba) << "round " << round;
    ASSERT_TRUE(bench.add(punch(10 - 5 * round, -8)));
    fc.show(bench, home, sh, {true, false, {}}, false);
    fc.flush(all);
    EXPECT_EQ(fc.frame().rgba, fullRender(pool, bench, home, sh).rgba) << "round " << round;
  }
  EXPECT_EQ(fc.counters().fieldRebuilds, 2u);
  // A third model takes the renderer used longest ago; a model made where a destroyed one was
  // (same address, same workpiece) is not mistaken for it.
  auto next = std::make_unique<Model>(plate, Deformation::Sheet);
  ASSERT_TRUE(next->add(punch(0, 0)));
  fc.show(*next, home, sh, {true, false, {}}, false);
  fc.flush(all);
  EXPECT_EQ(fc.counters().fieldRebuilds, 3u);
  next.reset();
  fc.show(bench, home, sh, {true, false, {}}, false);
  fc.flush(all);
  next = std::make_unique<Model>(plate, Deformation::Sheet);
  ASSERT_TRUE(next->add(punch(12, 3)));
  ASSERT_TRUE(next->add(punch(-12, 3)));
  fc.show(*next, home, sh, {true, false, {}}, false);
  fc.flush(all);
  EXPECT_EQ(fc.frame().rgba, fullRender(pool, *next, home, sh).rgba);
}

TEST(FrameComposer, MergesOverlappingRectangles) {
  const auto r = mergeRects({{0, 0, 10, 10}, {5, 0, 10, 10}, {100, 100, 5, 5}, {0, 0, 0, 0}});
  ASSERT_EQ(r.size(), 2u);
  EXPECT_EQ(r[0].w, 15);
  EXPECT_EQ(r[1].x, 100);
}

TEST(FrameComposer, MergesSpansWhereThatTracesLittleMore) {
  // Two overlapping round spans become one; a far one stays apart; the merged spans hold both and
  // no row wider than the two spans' hull.
  auto disc = [](int cx, int cy, int r) {
    PixelSpans s;
    s.box = {cx - r, cy - r, 2 * r + 1, 2 * r + 1};
    for (int y = -r; y <= r; ++y) {
      const int half = static_cast<int>(std::sqrt(static_cast<double>(r * r - y * y)));
      s.rows.push_back({cx - half, cx + half + 1});
    }
    return s;
  };
  const PixelSpans a = disc(50, 50, 20), b = disc(60, 55, 20), far = disc(300, 50, 20);
  const auto m = mergeSpans({a, b, far, PixelSpans{}});
  ASSERT_EQ(m.size(), 2u);
  for (int y = 0; y < 100; ++y)
    for (int x = 0; x < 100; ++x)
      if (a.contains(x, y) || b.contains(x, y)) {
        ASSERT_TRUE(m[0].contains(x, y)) << x << "," << y;
      }
  EXPECT_LT(m[0].area(), m[0].box.area());
  EXPECT_EQ(m[1].box.x, far.box.x);
  // Side by side in the same rows far apart: merging would trace the gap, so they stay two.
  EXPECT_EQ(mergeSpans({disc(50, 50, 10), disc(200, 50, 10)}).size(), 2u);
}

}  // namespace
}  // namespace emboss
