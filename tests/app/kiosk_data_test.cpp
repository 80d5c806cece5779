// The kiosk's shipped data equal the code that makes them: the attract pieces (firmware-app/pieces)
// and the demo recording (tests/app/data). EMBOSS_UPDATE_KIOSK_DATA=1 rewrites them instead.
#include <algorithm>
#include <cmath>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cstdlib>
#include <set>

#include "app/attract_library.h"
#include "demo_recording.h"
#include "pieces/pieces.h"
#include "scene/scene.h"
#include "test_support.h"

namespace emboss {
namespace {

namespace fs = std::filesystem;

bool updating() {
  const char* e = std::getenv("EMBOSS_UPDATE_KIOSK_DATA");
  return e && *e && std::string(e) != "0";
}

// Structure and strings equal, numbers equal within 1e-12 relative (or 1e-12 absolute near zero).
bool sameJson(const nlohmann::json& a, const nlohmann::json& b, const std::string& at, std::string& why) {
  if (a.is_number() && b.is_number()) {
    const double x = a.get<double>(), y = b.get<double>();
    if (std::abs(x - y) <= 1e-12 * std::max({1.0, std::abs(x), std::abs(y)})) return true;
    why = at + " (" + a.dump() + " against " + b.dump() + ")";
    return false;
  }
  if (a.type() != b.type() || a.size() != b.size()) {
    why = at + " (" + a.type_name() + " of " + std::to_string(a.size()) + " against " + b.type_name() + " of " +
          std::to_string(b.size()) + ")";
    return false;
  }
  if (a.is_object()) {
    for (auto it = a.begin(); it != a.end(); ++it)
      if (!b.contains(it.key()) || !sameJson(it.value(), b.at(it.key()), at + "/" + it.key(), why)) {
        if (why.empty()) why = at + "/" + it.key() + " (missing)";
        return false;
      }
    return true;
  }
  if (a.is_array()) {
    for (size_t i = 0; i < a.size(); ++i)
      if (!sameJson(a[i], b[i], at + "/" + std::to_string(i), why)) return false;
    return true;
  }
  if (a != b) {
    why = at + " (" + a.dump() + " against " + b.dump() + ")";
    return false;
  }
  return true;
}

TEST(AttractPieces, ShippedFilesEqualTheGenerator) {
  const fs::path dir = fs::path(EMBOSS_SOURCE_DIR) / "firmware-app" / "pieces";
  const auto pieces = generateAttractPieces();
  ASSERT_GE(pieces.size(), 3u);
  std::set<std::string> names;
  for (const auto& p : pieces) {
    names.insert(p.file);
    EXPECT_GE(p.scene.operations.size(), 300u) << p.file << ": several hundred operations";
    EXPECT_LE(p.scene.operations.size(), 4000u) << p.file;
    auto model = p.scene.makeModel();
    EXPECT_TRUE(model) << p.file << ": " << (model ? "" : model.error());
    const std::string json = sceneToJson(p.scene);
    if (updating()) {
      ASSERT_TRUE(writeFileAtomically(dir / p.file, json));
      continue;
    }
    // Equal as JSON, numbers within a few units in the last place: the generator calls sin() and
    // cos(), whose last bit glibc does not promise to be the same on every machine (x86 picks an
    // FMA variant at run time; arm64 has its own).
    std::string why;
    EXPECT_TRUE(sameJson(nlohmann::json::parse(test::readText(dir / p.file)), nlohmann::json::parse(json), "", why))
        << p.file << " differs from src/pieces at " << why << ": run `emboss-kiosk --write-pieces firmware-app/pieces`";
  }
  // Every file there plays (other pieces may join the generated ones).
  std::vector<std::string> log;
  const auto loaded = loadAttractPieces(dir, [&](const std::string& l) { log.push_back(l); });
  EXPECT_TRUE(log.empty()) << log.front();
  std::set<std::string> found;
  for (const auto& l : loaded) found.insert(l.name + ".json");
  for (const auto& n : names) EXPECT_TRUE(found.count(n)) << n << " does not play";
}

TEST(AttractPieces, AreDeterministic) {
  const auto a = generateAttractPieces(), b = generateAttractPieces();
  ASSERT_EQ(a.size(), b.size());
  for (size_t i = 0; i < a.size(); ++i) EXPECT_EQ(sceneToJson(a[i].scene), sceneToJson(b[i].scene));
}

// The recordings in tests/app/data are their generators' text (tests/app/demo_recording.h).
void expectFileEquals(const char* name, const std::string& text) {
  const fs::path file = fs::path(EMBOSS_SOURCE_DIR) / "tests" / "app" / "data" / name;
  if (updating()) {
    ASSERT_TRUE(writeFileAtomically(file, text));
    return;
  }
  EXPECT_EQ(test::readText(file), text) << "run the test with EMBOSS_UPDATE_KIOSK_DATA=1 to rewrite " << file;
}

TEST(KioskData, DemoRecordingFileEqualsItsGenerator) { expectFileEquals("visitor-demo.events", test::visitorDemoRecording()); }

TEST(KioskData, BigRegionsRecordingFileEqualsItsGenerator) { expectFileEquals("big-regions.events", test::bigRegionsRecording()); }

}  // namespace
}  // namespace emboss
