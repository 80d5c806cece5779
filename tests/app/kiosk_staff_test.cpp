// The kiosk's staff side, headless under a fake clock: the staff screen, the one export (the menu's
// and embossctl's) run off the main loop with its progress, and the session store it copies from.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <fstream>
#include <thread>

#include "app/kiosk_app.h"
#include "app/memory_display.h"
#include "kiosk_fixtures.h"
#include "test_support.h"

namespace emboss {
namespace {

namespace fs = std::filesystem;
using test::kH;
using test::kW;
using test::testConfig;
using test::tinyPieces;

// Steps the kiosk (its clock standing still) until the export under way is over.
void stepUntilExported(KioskApp& app) {
  for (int i = 0; i < 2000 && app.exporting(); ++i) {
    app.step();
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  ASSERT_FALSE(app.exporting());
}

// A session saved earlier (session-20240101-120000.json), for the staff screen to export.
::testing::AssertionResult saveOneSession(const KioskConfig& config) {
  fs::create_directories(config.sessionsDir);
  Scene s;
  s.workpiece = std::make_shared<Plate>(60.0, 40.0, 0.5);
  Model m(s.workpiece, Deformation::Sheet);
  if (Status st = saveScene(s, &m, config.sessionsDir / "session-20240101-120000.json"); !st)
    return ::testing::AssertionFailure() << st.error();
  return ::testing::AssertionSuccess();
}

KioskStart staffStart() {
  KioskStart start;
  start.staff = true;
  return start;
}

TEST(KioskApp, StaffExportsSessionsAndSaysWhyWhenItCannot) {
  const fs::path dir = test::scratchDir("kiosk-app-staff");
  double t = 0;
  MemoryDisplay display(kW, kH);
  KioskConfig config = testConfig(dir);
  // A session saved earlier.
  ASSERT_TRUE(saveOneSession(config));
  std::vector<std::string> log;
  KioskApp app(config, tinyPieces(), display, [&](const std::string& l) { log.push_back(l); }, [&] { return t; }, staffStart());
  EXPECT_EQ(app.mode(), KioskMode::Staff);
  app.step();
  // The export folder is missing (no USB stick): a clear message, nothing else happens.
  app.staffActivate(1);
  EXPECT_NE(app.staffMessage().find("is not a folder"), std::string::npos) << app.staffMessage();
  EXPECT_FALSE(app.exporting());
  // A folder on the kiosk's own disk is not a stick: refused as embossctl's export is (where the
  // test's folder is on the root file system; a tmpfs would be a file system of its own).
  fs::create_directories(config.exportDir);
  const Status stick = checkExportDestination(config.exportDir, false);
  app.staffActivate(1);
  if (!stick) {
    EXPECT_EQ(app.staffMessage(), stick.error());
    EXPECT_FALSE(app.exporting());
    EXPECT_TRUE(fs::is_empty(config.exportDir));
  }
  stepUntilExported(app);
}

TEST(KioskApp, StaffMenuExportRunsOffTheMainLoopAndShowsItsOutcome) {
  const fs::path dir = test::scratchDir("kiosk-app-staff-export");
  double t = 0;
  MemoryDisplay display(kW, kH);
  KioskConfig config = testConfig(dir);
  config.exportAnyDir = true;  // the test's folder stands for a stick
  ASSERT_TRUE(saveOneSession(config));
  std::vector<std::string> log;
  KioskApp app(config, tinyPieces(), display, [&](const std::string& l) { log.push_back(l); }, [&] { return t; }, staffStart());
  app.step();
  fs::create_directories(config.exportDir);
  app.staffActivate(1);
  EXPECT_TRUE(app.exporting());
  EXPECT_EQ(app.staffMessage().rfind("Exporting to ", 0), 0u) << app.staffMessage();
  app.staffActivate(1);  // a second one while the first runs
  EXPECT_NE(app.staffMessage().find("already under way"), std::string::npos) << app.staffMessage();
  stepUntilExported(app);
  EXPECT_EQ(app.staffMessage().rfind("Exported 1 files", 0), 0u) << app.staffMessage();
  EXPECT_TRUE(std::any_of(log.begin(), log.end(), [](const std::string& l) { return l.rfind("staff: Exported 1 files", 0) == 0; }));
  bool found = false;
  for (const auto& e : fs::recursive_directory_iterator(config.exportDir)) found |= e.path().filename() == "session-20240101-120000.json";
  EXPECT_TRUE(found);
  // The staff socket's export goes through the same export: progress lines, then the answer.
  const fs::path stick2 = dir / "export2";
  fs::create_directories(stick2);
  EXPECT_FALSE(app.staffCommand(R"({"cmd":"export","dest":")" + stick2.string() + R"(","allow_any_dir":true,"progress":true})"));
  EXPECT_TRUE(app.exporting());
  std::vector<StaffProgress> progress;
  std::optional<std::string> answer;
  for (int i = 0; i < 2000 && !answer; ++i) {
    app.step();
    StaffPending p = app.staffPoll();
    for (const auto& line : p.progress) {
      auto pr = parseStaffProgress(line);
      ASSERT_TRUE(pr) << line;
      progress.push_back(*pr);
    }
    answer = p.answer;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  ASSERT_TRUE(answer);
  EXPECT_NE(answer->find("\"ok\":true"), std::string::npos) << *answer;
  ASSERT_FALSE(progress.empty());
  EXPECT_EQ(progress.back().sessionsDone, 1u);
  EXPECT_EQ(progress.back().sessions, 1u);
  EXPECT_EQ(app.staffMessage().rfind("Exported 1 files", 0), 0u) << app.staffMessage();
  // Refusals answer at once.
  const auto refused = app.staffCommand(R"({"cmd":"export","dest":"/no/such/stick"})");
  ASSERT_TRUE(refused);
  EXPECT_NE(refused->find("\"ok\":false"), std::string::npos);
  EXPECT_TRUE(fs::exists(config.sessionsDir / "session-20240101-120000.json"));  // never moved
  // Back to the exhibit.
  QueuedButtons buttons;
  app.addButtons(&buttons);
  buttons.tap(Action::Turn, t);  // activates the selected entry: "back to the exhibit"
  app.step();
  EXPECT_EQ(app.mode(), KioskMode::Attract);
}

TEST(KioskApp, StaffScreenNamesAnUnusableTabletWithTheReason) {
  const fs::path dir = test::scratchDir("kiosk-app-notes");
  double t = 0;
  MemoryDisplay display(kW, kH);
  KioskStart start;
  start.staff = true;
  KioskApp app(testConfig(dir), tinyPieces(), display, {}, [&] { return t; }, start);
  const std::string why =
      "no tablet found: /dev/hidraw0 (device 256c:006d: its report descriptor describes no pen (digitizer stylus with X and Y))";
  app.setDeviceNote("Tablet", why);
  app.step();
  std::string all;
  for (const auto& l : app.staffLines()) {
    EXPECT_LE(l.size(), 58u) << l;  // wrapped to fit beside the menu
    all += (all.empty() ? "" : " ") + (l.rfind("  ", 0) == 0 ? l.substr(2) : l);
  }
  EXPECT_NE(all.find("Tablet: " + why), std::string::npos) << all;
  app.setDeviceNote("Tablet", "");
  t += 0.1;
  app.step();
  for (const auto& l : app.staffLines()) EXPECT_EQ(l.find("Tablet:"), std::string::npos) << l;
}

TEST(SessionStore, FullDiskForExportIsAClearMessageAndNothingIsCopied) {
  const fs::path dir = test::scratchDir("session-store-full");
  SessionStore store(dir / "sessions", {});
  Scene s;
  s.workpiece = std::make_shared<Plate>(60.0, 40.0, 0.5);
  Model m(s.workpiece, Deformation::Sheet);
  ASSERT_TRUE(store.save(s, m, nullptr, "20240101-000000"));
  fs::create_directories(dir / "stick");
  auto r = store.exportAll(dir / "stick", "x", std::nullopt, [](const fs::path&) { return std::optional<std::uintmax_t>(1000); });
  ASSERT_FALSE(r);
  EXPECT_NE(r.error().find("not enough space"), std::string::npos) << r.error();
  EXPECT_TRUE(fs::is_empty(dir / "stick"));
}

TEST(SessionStore, AFailedSaveIsKeptAndWrittenLater) {
  const fs::path dir = test::scratchDir("session-store-retry");
  std::ofstream(dir / "blocked") << "a file where the folder should be";
  std::vector<std::string> log;
  SessionStore store(dir / "blocked" / "sessions", [&](const std::string& l) { log.push_back(l); });
  Scene s;
  s.workpiece = std::make_shared<Plate>(60.0, 40.0, 0.5);
  Model m(s.workpiece, Deformation::Sheet);
  Operation op;
  op.kind = OpKind::Punch;
  op.a = 3, op.p = 0.2, op.at = {0, 0, 0.5};
  ASSERT_TRUE(m.add(op));
  Image picture(8, 8);
  EXPECT_FALSE(store.save(s, m, &picture, "20240101-000000"));
  EXPECT_EQ(store.pendingCount(), 1u);
  ASSERT_FALSE(log.empty());
  EXPECT_NE(log[0].find("keeping the session"), std::string::npos) << log[0];
  EXPECT_EQ(store.retryPending(), 1u);  // still blocked
  fs::remove(dir / "blocked");
  EXPECT_EQ(store.retryPending(), 0u);
  ASSERT_EQ(store.list().size(), 1u);
  EXPECT_EQ(loadScene(store.list()[0])->operations.size(), 1u);
  EXPECT_TRUE(fs::exists(dir / "blocked" / "sessions" / "session-20240101-000000.png"));
}

}  // namespace
}  // namespace emboss
