// The staff export's take-home files: made beside each session's copy, counted, and a failure to
// make one is a warning while the session itself is still copied.
#include <gtest/gtest.h>

#include <filesystem>

#include "app/kiosk_config.h"
#include "app/session_store.h"
#include "export/take_home.h"
#include "frep/workpieces.h"
#include "test_support.h"

namespace emboss {
namespace {

namespace fs = std::filesystem;

TEST(TakeHome, SetParsesAndPrints) {
  auto set = parseTakeHomeSet("postcard, heightmap");
  ASSERT_TRUE(set.ok());
  EXPECT_TRUE(set->postcard && set->heightmap && !set->stl && !set->threemf);
  EXPECT_EQ(takeHomeSetText(*set), "postcard,heightmap");
  EXPECT_EQ(takeHomeSetText(*parseTakeHomeSet("none")), "none");
  EXPECT_EQ(takeHomeSetText(*parseTakeHomeSet("stl,3mf")), "stl,3mf");
  EXPECT_FALSE(parseTakeHomeSet("postcard,gif").ok());
  EXPECT_NE(parseTakeHomeSet("gif").error().find("'gif'"), std::string::npos);
  EXPECT_FALSE(parseTakeHomeSet("none,stl").ok());
  EXPECT_GT(parseTakeHomeSet("stl")->allowance(), parseTakeHomeSet("postcard")->allowance());
  std::vector<std::string> warnings;
  KioskConfig c = parseKioskConfig("take_home = stl\n", "k.conf", KioskConfig{}, warnings);
  EXPECT_TRUE(warnings.empty());
  EXPECT_EQ(takeHomeSetText(c.takeHome), "stl");
  c = parseKioskConfig("take_home = jpeg\n", "k.conf", KioskConfig{}, warnings);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_EQ(takeHomeSetText(c.takeHome), "none") << "a bad line keeps the default";
}

TEST(TakeHome, StaffExportMakesThemBesideEachSession) {
  const fs::path dir = test::scratchDir("take-home-export");
  SessionStore store(dir / "sessions", {});
  Scene s;
  s.title = "Visitor's rosette";
  s.workpiece = std::make_shared<Plate>(20.0, 15.0, 0.5);
  Model m(s.workpiece, Deformation::Sheet);
  Operation punch;
  punch.kind = OpKind::Punch;
  punch.a = 3, punch.p = 0.5, punch.q = 1, punch.at = {0, 0, 0.5};
  ASSERT_TRUE(m.add(punch));
  ASSERT_TRUE(store.save(s, m, nullptr, "20240101-000000"));
  fs::create_directories(dir / "stick");
  auto set = *parseTakeHomeSet("heightmap,postcard,stl");
  ExportTakeHome hook;
  hook.allowance = set.allowance();
  hook.make = [&](const fs::path& scene) -> Result<std::pair<size_t, std::uintmax_t>> {
    auto w = writeTakeHomeFiles(scene, set, nullptr);
    if (!w) return fail(w.error());
    return std::make_pair(w->files, w->bytes);
  };
  auto r = store.exportAll(dir / "stick", "x", std::nullopt, {}, 0, {}, nullptr, hook);
  ASSERT_TRUE(r.ok()) << r.error();
  EXPECT_TRUE(r->warnings.empty());
  EXPECT_EQ(r->files, 4u);  // the scene, the height map, the postcard, the STL
  size_t found = 0;
  for (const auto& e : fs::directory_iterator(r->folder)) {
    const std::string name = e.path().filename().string();
    EXPECT_EQ(name.find(".tmp"), std::string::npos) << name;
    found += name.find(".height.png") != std::string::npos || name.find(".postcard.png") != std::string::npos ||
             name.find(".stl") != std::string::npos;
    EXPECT_GT(fs::file_size(e.path()), 0u) << name;
  }
  EXPECT_EQ(found, 3u);

  // A take-home file that cannot be made: a warning, and the session is still copied.
  hook.make = [](const fs::path& scene) -> Result<std::pair<size_t, std::uintmax_t>> {
    return fail(scene.filename().string() + ": the disk said no");
  };
  auto r2 = store.exportAll(dir / "stick", "y", std::nullopt, {}, 0, {}, nullptr, hook);
  ASSERT_TRUE(r2.ok()) << r2.error();
  EXPECT_EQ(r2->files, 1u);
  ASSERT_EQ(r2->warnings.size(), 1u);
  EXPECT_NE(r2->warnings[0].find("the disk said no"), std::string::npos);
}

}  // namespace
}  // namespace emboss
