// The whole kiosk, headless, under a fake clock: a recorded visitor replayed, sessions saved,
// capture drawing, attract mode, and the fallbacks when files or devices misbehave. The staff
// screen, exports and the session store: kiosk_staff_test.cpp.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <thread>

#include "app/attract_library.h"
#include "app/kiosk_app.h"
#include "app/memory_display.h"
#include "app/pointer_input.h"
#include "app/stroke_builder.h"
#include "demo_recording.h"
#include "input/evemu.h"
#include "pen/pen_replay.h"
#include "kiosk_fixtures.h"
#include "test_support.h"

namespace emboss {
namespace {

namespace fs = std::filesystem;
using test::demoSamples;
using test::kH;
using test::kW;
using test::testConfig;
using test::tinyPieces;

// What the session must hold: the recording's strokes through the kiosk's mapping, picking and
// the catalogue, tools switched by the barrel button, computed here without the kiosk.
std::vector<Operation> expectedOperations(const std::vector<PenSample>& samples, const Workbench& bench) {
  Model model(bench.model().workpiecePtr(), Deformation::Sheet);
  const Camera cam(bench.homeCamera(), kW, kH);
  const ScreenBox area = tabletArea(sheetOnScreen(cam, model.workpiece().bounds()), 1.6);
  const Metal metal = *metalByName("copper");
  size_t tool = 1;  // a visitor starts with the tracer
  bool barrel = false;
  StrokeBuilder sb;
  std::vector<Operation> all;
  auto end = [&] {
    if (!sb.active()) return;
    const size_t handed = sb.handedOut();
    auto f = sb.end();
    EXPECT_EQ(f.keep, handed);
    for (auto& op : f.rest) {
      EXPECT_TRUE(model.add(op));
      all.push_back(op);
    }
  };
  for (const auto& s : samples) {
    if (s.barrel1 && !barrel) {
      end();
      tool = (tool + 1) % toolCatalogue().size();
    }
    barrel = s.barrel1;
    if (!s.tip) {
      end();
      continue;
    }
    const auto hit = pickSurface(model, cam, area.x + s.x * area.w, area.y + s.y * area.h);
    if (!hit) {
      end();
      continue;
    }
    if (!sb.active()) sb.begin(toolCatalogue()[tool], metal);
    for (auto& op : sb.add({hit->x, hit->y, hit->z, std::clamp(s.pressure, 0.0, 1.0)})) {
      EXPECT_TRUE(model.add(op));
      all.push_back(op);
    }
  }
  end();
  return all;
}

double pixelDiff(const Image& a, const Image& b, int x, int y) {
  double d = 0;
  for (int k = 0; k < 3; ++k) d += std::abs(int(a.pixel(x, y)[k]) - int(b.pixel(x, y)[k]));
  return d;
}

TEST(KioskApp, RecordedVisitorBecomesTheSessionAndTheSnapshotShowsIt) {
  const fs::path dir = test::scratchDir("kiosk-app-replay");
  double t = 100.0;
  MemoryDisplay display(kW, kH);
  std::vector<std::string> log;
  KioskApp app(testConfig(dir), tinyPieces(), display, [&](const std::string& l) { log.push_back(l); }, [&] { return t; });
  EXPECT_EQ(app.mode(), KioskMode::Attract);
  const auto samples = demoSamples();
  ReplayPen pen(samples, "demo", true);
  app.setPen(&pen, PenMapping::Tablet, true);
  // (The pen on the model, as the replay below finds it: through the renderer the metal is the
  // traced picture's, a micrometre off the model's, and whether a big region's field is still
  // rising decides which.)
  app.setPickThroughRenderer(false);
  int steps = 0;
  while (!app.feedDone() && steps < 100000) {
    app.step();
    t += 0.01;
    ++steps;
  }
  EXPECT_EQ(app.mode(), KioskMode::Visitor);
  app.finish();

  // The session: exactly the operations of the recorded strokes (the waking stroke included).
  const auto want = expectedOperations(samples, app.bench());
  const Model& got = app.bench().model();
  ASSERT_EQ(got.activeCount(), want.size());
  EXPECT_GT(want.size(), 100u);
  for (size_t i = 0; i < want.size(); ++i) ASSERT_TRUE(sameOperation(got.operations()[i].op(), want[i])) << "operation " << i;
  size_t regions = 0, traces = 0, punches = 0;
  for (const auto& op : want) regions += op.kind == OpKind::Region, traces += op.kind == OpKind::Trace, punches += op.kind == OpKind::Punch;
  EXPECT_EQ(regions, 8u);
  EXPECT_GT(traces, 50u);
  EXPECT_EQ(punches, 16u);  // the boss and fifteen beads
  EXPECT_EQ(app.bench().strokes(), 10u + 8u + 1u + 15u);  // traced, raised, the boss, the beads

  // Written at exit as a scene file, and saved among the sessions (the kiosk stopping).
  ASSERT_TRUE(app.writeSession(dir / "out" / "session.json"));
  auto scene = loadScene(dir / "out" / "session.json");
  ASSERT_TRUE(scene) << scene.error();
  EXPECT_EQ(scene->operations.size(), want.size());
  EXPECT_EQ(app.sessions().list().size(), 1u);

  // The picture: changed where the strokes are, untouched far from them.
  ThreadPool pool(2);
  Renderer r(pool);
  Model blankModel(got.workpiecePtr(), Deformation::Sheet);
  r.sync(blankModel);
  r.setCamera(Camera(app.bench().homeCamera(), kW, kH));
  r.setShading(app.bench().shading());
  Image blank;
  r.renderFull(blank);
  const Image& frame = app.composer().frame();
  const Camera cam(app.bench().homeCamera(), kW, kH);
  int changedNearStrokes = 0, checked = 0;
  for (size_t i = 0; i < want.size(); i += 7) {
    const Operation& op = want[i];
    const Vec2 p = op.kind == OpKind::Punch ? Vec2{op.at.x, op.at.y} : op.points.front();
    const auto s = cam.project({p.x, p.y, 0.5});
    double best = 0;
    for (int dy = -3; dy <= 3; ++dy)
      for (int dx = -3; dx <= 3; ++dx) best = std::max(best, pixelDiff(frame, blank, int(s->x) + dx, int(s->y) + dy));
    changedNearStrokes += best > 30;
    ++checked;
  }
  EXPECT_GE(changedNearStrokes, checked * 9 / 10);
  // The sheet's right end is far from the flower: the same as the bare sheet there.
  const auto far = cam.project({50, 0, 0.5});
  for (int dy = -5; dy <= 5; ++dy)
    for (int dx = -5; dx <= 5; ++dx) EXPECT_EQ(pixelDiff(frame, blank, int(far->x) + dx, int(far->y) + dy), 0.0);
  // The snapshot is the frame with the overlay.
  ASSERT_TRUE(app.writeSnapshot(dir / "out" / "snap.png"));
  auto png = readPng(dir / "out" / "snap.png");
  ASSERT_TRUE(png);
  EXPECT_EQ(png->width, kW);
  const auto& latency = app.latency();
  EXPECT_GT(latency.count(), 20u);
}

// Six raised regions over most of the sheet (tests/app/data/big-regions.events): each rises a band
// of rows a turn (Renderer::continueField), and the finished frame is a full render's.
TEST(KioskApp, BigRegionsRiseToTheExactFrame) {
  const fs::path dir = test::scratchDir("kiosk-app-regions");
  double t = 100.0;
  MemoryDisplay display(kW, kH);
  KioskApp app(testConfig(dir), tinyPieces(), display, {}, [&] { return t; });
  auto rec = parseEvemu(test::bigRegionsRecording());
  ASSERT_TRUE(rec) << rec.error();
  auto samples = evemuToSamples(*rec);
  ASSERT_TRUE(samples) << samples.error();
  ReplayPen pen(*samples, "regions", true);
  app.setPen(&pen, PenMapping::Tablet, true);
  const size_t tool = app.bench().toolIndex();
  for (int steps = 0; !app.feedDone() && steps < 100000; ++steps) {
    app.step();
    t += 0.01;
  }
  app.finish();
  const Model& got = app.bench().model();
  size_t regions = 0;
  for (size_t i = 0; i < got.activeCount(); ++i) regions += got.operations()[i].op().kind == OpKind::Region;
  EXPECT_EQ(regions, 6u);
  EXPECT_EQ(app.bench().toolIndex(), tool) << "the recording ends with the tool it began with (it is played in a loop)";
  EXPECT_FALSE(app.composer().pending());
  ThreadPool pool(2);
  Renderer r(pool);
  r.sync(got);
  r.setCamera(Camera(app.bench().homeCamera(), kW, kH));
  r.setShading(app.bench().shading());
  Image full;
  r.renderFull(full);
  EXPECT_EQ(app.composer().frame().rgba, full.rgba);
}

TEST(KioskApp, IdleVisitorIsSavedAndAttractResumes) {
  const fs::path dir = test::scratchDir("kiosk-app-idle");
  double t = 0;
  MemoryDisplay display(kW, kH);
  KioskConfig config = testConfig(dir);
  KioskApp app(config, tinyPieces(), display, {}, [&] { return t; });
  QueuedButtons buttons;
  app.addButtons(&buttons);
  // A visitor's tap (three samples: hover, touch, lift) with the punch.
  buttons.tap(Action::NextTool, t);  // wakes the kiosk, and is carried out: the wide tracer
  app.step();
  EXPECT_EQ(app.mode(), KioskMode::Visitor);
  EXPECT_EQ(app.bench().toolIndex(), 2u);
  std::vector<PenSample> tap = {{0, 0.5, 0.5, 0, false, true}, {0.01, 0.5, 0.5, 0.7, true, true}, {0.02, 0.51, 0.5, 0.7, true, true},
                                {0.03, 0.52, 0.5, 0, false, true}};
  ReplayPen pen(tap, "tap", true);
  app.setPen(&pen, PenMapping::Tablet, true);
  for (int i = 0; i < 5; ++i) app.step(), t += 0.02;
  ASSERT_GT(app.bench().model().activeCount(), 0u);
  // The log's lines are about the session in the journal (journald's EMBOSS_SESSION field).
  ASSERT_TRUE(app.journal());
  const auto journalled = app.journal()->list();
  ASSERT_FALSE(journalled.empty());
  EXPECT_EQ(logSession(), journalled.back().id);
  t += config.idleSeconds + 0.5;
  app.step();
  EXPECT_EQ(app.mode(), KioskMode::StillThere);
  t += config.countdownSeconds + 0.5;
  app.step();
  EXPECT_EQ(app.mode(), KioskMode::Attract);
  EXPECT_EQ(logSession(), 0);  // saved and ended: the lines that follow are about no session
  const auto saved = app.sessions().list();
  ASSERT_EQ(saved.size(), 1u);
  auto scene = loadScene(saved[0]);
  ASSERT_TRUE(scene) << scene.error();
  EXPECT_GT(scene->operations.size(), 0u);
  fs::path png = saved[0];
  png.replace_extension(".png");
  EXPECT_TRUE(fs::exists(png));
  // No temporary files left behind.
  for (const auto& e : fs::directory_iterator(config.sessionsDir)) EXPECT_NE(e.path().extension(), ".part");
  EXPECT_EQ(app.bench().model().activeCount(), 0u);
}

TEST(KioskApp, NewSheetSavesTheOldOneAndUndoNeverLosesTheSession) {
  const fs::path dir = test::scratchDir("kiosk-app-newsheet");
  double t = 0;
  MemoryDisplay display(kW, kH);
  KioskApp app(testConfig(dir), tinyPieces(), display, {}, [&] { return t; });
  QueuedButtons buttons;
  app.addButtons(&buttons);
  std::vector<PenSample> s;
  for (int i = 0; i <= 40; ++i) s.push_back({i * 0.005, 0.3 + 0.01 * i, 0.5, 0.6, true, true});
  s.push_back({0.3, 0.7, 0.5, 0, false, true});
  ReplayPen pen(s, "line", true);
  app.setPen(&pen, PenMapping::Tablet, true);
  while (!app.feedDone()) app.step(), t += 0.01;
  const size_t ops = app.bench().model().activeCount();
  ASSERT_GT(ops, 0u);
  buttons.tap(Action::NewSheet, t);
  app.step();
  EXPECT_EQ(app.bench().model().activeCount(), 0u);
  ASSERT_EQ(app.sessions().list().size(), 1u);
  EXPECT_EQ(loadScene(app.sessions().list()[0])->operations.size(), ops);
}

// A camera whose still is a drawing on a sheet of paper (a circle, landscape A-format) lying on a
// dark table; or one that fails, as an unplugged camera does.
class FakeCamera final : public CameraSource {
 public:
  std::string name() const override { return "fake camera"; }
  Result<Image> capture() override {
    ++captures;
    if (broken) return fail("camera: fake is gone (unplugged?)");
    Image img(640, 480);
    for (int y = 0; y < img.height; ++y)
      for (int x = 0; x < img.width; ++x) {
        const bool paper = x >= 90 && x < 550 && y >= 78 && y < 404;  // 460 x 326: about sqrt 2
        const double r = std::hypot(x - 320.0, y - 241.0);
        const bool ink = paper && drawing && std::fabs(r - 95) < 2.5;
        const std::uint8_t v = ink ? 35 : paper ? 228 : 70;
        std::uint8_t* p = img.pixel(x, y);
        p[0] = v, p[1] = v, p[2] = paper ? v : 50, p[3] = 255;
      }
    return img;
  }
  bool present() override { return !broken; }
  bool broken = false;
  bool drawing = true;
  int captures = 0;
};

// Steps (the fake clock still) until the capture thread has answered.
void waitForCapture(KioskApp& app, double& t) {
  for (int i = 0; i < 3000 && app.capturePhase() == KioskApp::CapturePhase::Running; ++i) {
    app.step();
    t += 0.001;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
}

TEST(KioskApp, CapturedDrawingIsOfferedThenEmbossedAsOneStrokeOrPutAway) {
  const fs::path dir = test::scratchDir("kiosk-app-capture");
  double t = 0;
  MemoryDisplay display(kW, kH);
  std::vector<std::string> log;
  KioskApp app(testConfig(dir), tinyPieces(), display, [&](const std::string& l) { log.push_back(l); }, [&] { return t; });
  QueuedButtons buttons;
  app.addButtons(&buttons);

  // No camera: the press wakes the kiosk and says so, nothing else.
  buttons.tap(Action::Capture, t);
  app.step();
  EXPECT_EQ(app.mode(), KioskMode::Visitor);
  EXPECT_EQ(app.capturePhase(), KioskApp::CapturePhase::Idle);
  EXPECT_EQ(app.captureMessage(), "No camera");

  FakeCamera camera;
  app.setCamera(&camera);
  buttons.tap(Action::Capture, t);
  app.step();
  EXPECT_EQ(app.capturePhase(), KioskApp::CapturePhase::Running);
  waitForCapture(app, t);
  ASSERT_EQ(app.capturePhase(), KioskApp::CapturePhase::Offer) << app.captureMessage();
  ASSERT_NE(app.captureOffer(), nullptr);
  const size_t offered = app.captureOffer()->operations.size();
  ASSERT_GT(offered, 0u);
  // The circle (95 px of the sheet's 326 px height) round the plate's centre; the sheet's height
  // maps onto the plate's 80 mm less 5 mm margins: a radius of 20.4 mm.
  for (const auto& line : app.captureOffer()->polylines)
    for (const Vec2& p : line) EXPECT_NEAR(std::hypot(p.x, p.y), 95.0 * 70.0 / 326.0, 1.5);
  EXPECT_EQ(app.bench().model().activeCount(), 0u);  // only offered so far
  // Capture again: embossed, as one stroke.
  buttons.tap(Action::Capture, t);
  app.step();
  EXPECT_EQ(app.capturePhase(), KioskApp::CapturePhase::Idle);
  EXPECT_EQ(app.bench().model().activeCount(), offered);
  EXPECT_EQ(app.bench().strokes(), 1u);
  buttons.tap(Action::Undo, t);
  app.step();
  EXPECT_EQ(app.bench().model().activeCount(), 0u);

  // Offered again, and put away with undo: nothing embossed, the strokes untouched.
  buttons.tap(Action::Capture, t);
  app.step();
  waitForCapture(app, t);
  ASSERT_EQ(app.capturePhase(), KioskApp::CapturePhase::Offer);
  const Image withGuide = display.screenshot();
  buttons.tap(Action::Undo, t);
  app.step();
  EXPECT_EQ(app.capturePhase(), KioskApp::CapturePhase::Idle);
  {
    // The guide was drawn over the plate where the circle's top lies, and is gone now.
    const Camera cam(app.bench().camera(), kW, kH);
    const auto top = cam.project({0.0, 95.0 * 70.0 / 326.0, 0.5});
    ASSERT_TRUE(top);
    const Image without = display.screenshot();
    int differ = 0;
    for (int dy = -3; dy <= 3; ++dy)
      for (int dx = -3; dx <= 3; ++dx) {
        const int x = std::clamp(int(top->x) + dx, 0, kW - 1), y = std::clamp(int(top->y) + dy, 0, kH - 1);
        differ += std::memcmp(withGuide.pixel(x, y), without.pixel(x, y), 3) != 0;
      }
    EXPECT_GT(differ, 3) << "no guide drawn near (" << top->x << ", " << top->y << ")";
  }
  EXPECT_EQ(app.captureOffer(), nullptr);
  EXPECT_EQ(app.bench().model().activeCount(), 0u);
  EXPECT_EQ(app.bench().strokes(), 0u);

  // A blank sheet: a message, nothing offered.
  camera.drawing = false;
  buttons.tap(Action::Capture, t);
  app.step();
  waitForCapture(app, t);
  EXPECT_EQ(app.capturePhase(), KioskApp::CapturePhase::Idle);
  EXPECT_NE(app.captureMessage().find("No drawing"), std::string::npos) << app.captureMessage();

  // The camera unplugged: the capture fails, the camera is reported lost and no longer used.
  camera.broken = true;
  buttons.tap(Action::Capture, t);
  app.step();
  waitForCapture(app, t);
  EXPECT_EQ(app.capturePhase(), KioskApp::CapturePhase::Idle);
  EXPECT_TRUE(app.cameraLost());
  const int before = camera.captures;
  buttons.tap(Action::Capture, t);
  app.step();
  EXPECT_EQ(camera.captures, before);
  EXPECT_EQ(app.captureMessage(), "No camera");
}

TEST(KioskApp, AnIdleCameraThatGoesAwayIsDroppedAndTheStaffMenuCaptures) {
  const fs::path dir = test::scratchDir("kiosk-app-camera-lost");
  double t = 0;
  MemoryDisplay display(kW, kH);
  KioskStart start;
  start.staff = true;
  KioskApp app(testConfig(dir), tinyPieces(), display, {}, [&] { return t; }, start);
  FakeCamera camera;
  app.setCamera(&camera);
  // From staff mode (entered from attract): the bench, a visitor's sheet, and the still.
  app.staffActivate(3);
  EXPECT_EQ(app.mode(), KioskMode::Visitor);
  EXPECT_EQ(app.capturePhase(), KioskApp::CapturePhase::Running);
  waitForCapture(app, t);
  EXPECT_EQ(app.capturePhase(), KioskApp::CapturePhase::Offer);
  // Unplugged while idle: noticed by the check every 2 s.
  camera.broken = true;
  app.step();
  EXPECT_FALSE(app.cameraLost());
  t += 2.5;
  app.step();
  EXPECT_TRUE(app.cameraLost());
  app.setCamera(nullptr);
  EXPECT_FALSE(app.cameraLost());
}

TEST(AttractLibrary, ABrokenPieceIsSkippedWithAMessage) {
  const fs::path dir = test::scratchDir("attract-broken");
  std::ofstream(dir / "a-broken.json") << "{\"operations\": [ {\"op\": \"punch\", \"a\": -1} ]";
  std::ofstream(dir / "b-bad-op.json") << R"({"operations": [{"op": "punch", "a": -2, "at": [0,0,0]}]})";
  ASSERT_TRUE(saveScene(tinyPieces()[0].scene, nullptr, dir / "c-good.json"));
  std::vector<std::string> log;
  const auto pieces = loadAttractPieces(dir, [&](const std::string& l) { log.push_back(l); });
  ASSERT_EQ(pieces.size(), 1u);
  EXPECT_EQ(pieces[0].name, "c-good");
  ASSERT_EQ(log.size(), 2u);
  EXPECT_NE(log[0].find("a-broken.json"), std::string::npos) << log[0];
  EXPECT_NE(log[1].find("b-bad-op.json"), std::string::npos) << log[1];
  EXPECT_TRUE(loadAttractPieces(dir / "missing", {}).empty());
  EXPECT_FALSE(builtinAttractPieces().empty());
}

TEST(KioskApp, AttractModeGoesOnWhereItWasAfterAStall) {
  const fs::path dir = test::scratchDir("kiosk-app-stall");
  double t = 0;
  MemoryDisplay display(kW, kH);
  KioskApp app(testConfig(dir), tinyPieces(), display, {}, [&] { return t; });
  app.step();
  ASSERT_EQ(app.mode(), KioskMode::Attract);
  const size_t before = app.attract().model().activeCount();
  // The loop stalls for a minute (longer than the whole piece): nothing is caught up at once.
  t += 60;
  app.step();
  EXPECT_EQ(app.attract().model().activeCount(), before);
  EXPECT_EQ(app.attract().pieceIndex(), 0u);
  // Steps at a normal pace: the piece goes on, one operation after the other.
  size_t seen = before, jumps = 0;
  for (int i = 0; i < 1000 && app.attract().model().activeCount() < 3; ++i) {
    t += 0.1;
    app.step();
    const size_t n = app.attract().model().activeCount();
    jumps += n > seen + 1;
    seen = n;
  }
  EXPECT_GE(app.attract().model().activeCount(), 3u);
  EXPECT_EQ(jumps, 0u);
}

// Attract mode is presented on a 30 Hz grid: whatever the loop's pace (here a turn every 7 ms, a
// pace that timing each frame from the last present would turn into 28 ms periods... or 35),
// 30 frames a second, each carrying what was traced since the last.
TEST(KioskApp, AttractModeIsPresentedThirtyTimesASecond) {
  const fs::path dir = test::scratchDir("kiosk-app-grid");
  double t = 0;
  MemoryDisplay display(kW, kH);
  KioskApp app(testConfig(dir), tinyPieces(), display, {}, [&] { return t; });
  app.step();
  ASSERT_EQ(app.mode(), KioskMode::Attract);
  for (double pace : {0.005, 0.007, 0.012}) {  // 4 s each
    const size_t before = app.presents();
    const double start = t;
    while (t < start + 4.0 - 1e-9) {
      t += pace;
      app.step();
    }
    // 120 ticks in 4 s; a turn lands on a tick at most one pace late, never skipping one.
    EXPECT_NEAR(static_cast<double>(app.presents() - before), 120.0, 1.0) << "a turn every " << pace * 1000 << " ms";
  }
}

// The kiosk's main loop sleeps as the app allows: while busy(), idleSeconds() (at most 5 ms); else
// up to wakeWithin() (at most 50 ms, the loop's cap). Attract mode still gets every 30 Hz tick; a
// visitor's still screen lets the loop sleep until input comes; the countdown is animated again.
TEST(KioskApp, TheLoopSleepsOnAStillScreenYetWakesForEveryTick) {
  const fs::path dir = test::scratchDir("kiosk-app-wake");
  double t = 0;
  MemoryDisplay display(kW, kH);
  KioskConfig config = testConfig(dir);
  KioskApp app(config, tinyPieces(), display, {}, [&] { return t; });
  auto sleep = [&] {
    const double wait = app.busy() ? std::min(0.005, app.idleSeconds()) : std::min(0.05, app.wakeWithin());
    t += std::max(wait, 1e-4);
  };
  app.step();
  ASSERT_EQ(app.mode(), KioskMode::Attract);
  const size_t before = app.presents();
  const double start = t;
  int turns = 0;
  while (t < start + 4.0 - 1e-9) sleep(), app.step(), ++turns;
  EXPECT_NEAR(static_cast<double>(app.presents() - before), 120.0, 1.0);
  EXPECT_LE(app.wakeWithin(), 1.0 / 30.0 + 1e-9);

  QueuedButtons buttons;
  app.addButtons(&buttons);
  buttons.tap(Action::NextTool, t);  // a visitor
  app.step();
  ASSERT_EQ(app.mode(), KioskMode::Visitor);
  for (int i = 0; i < 1000 && app.busy(); ++i) sleep(), app.step();
  ASSERT_FALSE(app.busy());
  EXPECT_EQ(app.wakeWithin(), std::numeric_limits<double>::infinity());  // nothing moves until input
  t += config.idleSeconds + 0.5;
  app.step();
  ASSERT_EQ(app.mode(), KioskMode::StillThere);
  EXPECT_LE(app.wakeWithin(), 1.0 / 30.0 + 1e-9);  // the countdown runs on the grid
}

TEST(AttractPlayer, PlaysPiecesOperationByOperationThenTurnsAndLoops) {
  auto pieces = tinyPieces();
  pieces.push_back(pieces[0]);
  pieces[1].scene.title = "second";
  AttractPlayer p(pieces, kW, kH);
  p.start(0, 0, 0.5);
  EXPECT_EQ(p.model().activeCount(), 3u);
  EXPECT_TRUE(p.takeChanges().full);
  const double build = p.buildSeconds(0);
  EXPECT_GE(build, 40.0);  // a watchable pace even for a tiny piece
  // Half was done at the start: the other half takes the other half of the time.
  p.update(build * 0.25);
  EXPECT_EQ(p.model().activeCount(), 4u);
  EXPECT_EQ(p.takeChanges().ops.size(), 1u);
  p.update(build * 0.5 + 0.01);
  EXPECT_EQ(p.model().activeCount(), 6u);
  p.update(build * 0.5 + 1);
  EXPECT_TRUE(p.moving());
  p.update(build * 0.5 + 1 + AttractPlayer::kShowSeconds);
  EXPECT_FALSE(p.moving());
  p.update(build * 0.5 + 2 + AttractPlayer::kShowSeconds + AttractPlayer::kRestSeconds);
  EXPECT_EQ(p.title(), "second");
  EXPECT_EQ(p.model().activeCount(), 0u);
}

TEST(KioskConfig, BadLinesAreWarningsAndKeepTheDefaults) {
  std::vector<std::string> w;
  const KioskConfig c = parseKioskConfig(
      "# comment\ndisplay = headless\nsize = 800x480\nidle_seconds = -3\nstaff_chord = undo+turn\nfoo = bar\n"
      "key.F5 = new_sheet\nmetal = gold\nnonsense line\ntablet = evemu:/tmp/x.events\n",
      "kiosk.conf", {}, w);
  EXPECT_EQ(c.display, "headless");
  EXPECT_EQ(c.width, 800);
  EXPECT_EQ(c.height, 480);
  EXPECT_EQ(c.idleSeconds, 60);
  EXPECT_EQ(c.staffChord.second, Action::Turn);
  EXPECT_EQ(c.keys.at("F5"), Action::NewSheet);
  EXPECT_EQ(c.keys.at("Right"), Action::NextTool);
  EXPECT_EQ(c.metal, "copper");
  EXPECT_EQ(c.tablet, "evemu:/tmp/x.events");
  ASSERT_EQ(w.size(), 4u);
  EXPECT_EQ(w[0].rfind("kiosk.conf:4: idle_seconds", 0), 0u) << w[0];
  std::vector<std::string> w2;
  loadKioskConfig("/nonexistent/kiosk.conf", {}, w2);
  ASSERT_EQ(w2.size(), 1u);
  EXPECT_NE(w2[0].find("using the defaults"), std::string::npos);
  // The camera: auto by default, a node or a picture, anything else a warning.
  EXPECT_EQ(c.camera, "auto");
  std::vector<std::string> w3;
  EXPECT_EQ(parseKioskConfig("camera = file:/tmp/drawing.png\n", "k", {}, w3).camera, "file:/tmp/drawing.png");
  EXPECT_EQ(parseKioskConfig("camera = /dev/video2\n", "k", {}, w3).camera, "/dev/video2");
  EXPECT_TRUE(w3.empty());
  EXPECT_EQ(parseKioskConfig("camera = webcam\n", "k", {}, w3).camera, "auto");
  ASSERT_EQ(w3.size(), 1u);
  EXPECT_NE(w3[0].find("camera must be"), std::string::npos) << w3[0];
  EXPECT_EQ(defaultKeyMap().at("c"), Action::Capture);
}

TEST(PointerInput, MouseIsAPenWithASteadyPressAndKeysAreButtons) {
  double t = 0;
  MousePen mouse(200, 100, [&] { return t; });
  mouse.feed({PointerEvent::Type::Move, 50, 25, ""});
  mouse.feed({PointerEvent::Type::Down, 50, 25, ""});
  t = 0.5;
  mouse.feed({PointerEvent::Type::Move, 100, 50, ""});
  mouse.feed({PointerEvent::Type::Up, 100, 50, ""});
  std::vector<PenSample> s;
  mouse.poll(s);
  ASSERT_EQ(s.size(), 4u);
  EXPECT_FALSE(s[0].tip);
  EXPECT_TRUE(s[0].inRange);
  EXPECT_DOUBLE_EQ(s[0].x, 0.25);
  EXPECT_TRUE(s[1].tip);
  EXPECT_GT(s[1].pressure, 0.3);
  EXPECT_NEAR(s[2].pressure, 0.6, 1e-9);
  EXPECT_DOUBLE_EQ(s[2].y, 0.5);
  EXPECT_FALSE(s[3].tip);
  KeyButtons keys(defaultKeyMap(), [&] { return t; });
  keys.feed({PointerEvent::Type::Key, 0, 0, "z"});
  keys.feed({PointerEvent::Type::Key, 0, 0, "unmapped"});
  std::vector<ButtonEvent> b;
  keys.poll(b);
  ASSERT_EQ(b.size(), 2u);
  EXPECT_EQ(b[0].action, Action::Undo);
  EXPECT_TRUE(b[0].pressed);
  EXPECT_FALSE(b[1].pressed);
}

TEST(MemoryDisplay, DrawsTheOverlayIntoThePicture) {
  MemoryDisplay d(40, 30);
  Image frame(40, 30);
  Overlay o;
  o.rects.push_back({5, 5, 10, 10, {1, 0, 0, 1}, 0});
  o.rings.push_back({30, 15, 6, 2, {0, 1, 0, 1}});
  o.texts.push_back({0, 0, 10, "skipped", {}});
  ASSERT_TRUE(d.present(frame, {}, o));
  const Image shot = d.screenshot();
  EXPECT_EQ(shot.pixel(10, 10)[0], 255);
  EXPECT_GT(shot.pixel(36, 15)[1], 240);
  EXPECT_EQ(shot.pixel(30, 15)[1], 0);  // the ring's middle stays clear
  EXPECT_EQ(d.textsSkipped(), 1u);
}

}  // namespace
}  // namespace emboss
