// The kiosk's configuration: comments that leave '#' in values alone, and the strict check of
// `emboss-kiosk --check-config` against the forgiving reading the kiosk does at start.
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "app/kiosk_config.h"

namespace emboss {
namespace {

namespace fs = std::filesystem;

KioskConfig parse(const std::string& text, std::vector<std::string>& warnings) {
  return parseKioskConfig(text, "k.conf", {}, warnings);
}

TEST(KioskConfig, HashInsideAValueIsNoComment) {
  std::vector<std::string> w;
  const KioskConfig c = parse("export_dir = /media/stick#2/exports\npieces_dir=/srv/a#b # the pieces\n"
                              "key.numbersign#x = undo\n",
                              w);
  EXPECT_TRUE(w.empty()) << w.front();
  EXPECT_EQ(c.exportDir, "/media/stick#2/exports");
  EXPECT_EQ(c.piecesDir, "/srv/a#b");
  EXPECT_EQ(c.keys.at("numbersign#x"), Action::Undo);
}

TEST(KioskConfig, CommentsAtTheStartOrAfterABlank) {
  std::vector<std::string> w;
  const KioskConfig c = parse("# a comment\n   # indented\n\t# after a tab\nmetal = brass # the default metal\n"
                              "idle_seconds = 30\t# after a tab\nthreads = 2#three\n",
                              w);
  EXPECT_EQ(c.metal, "brass");
  EXPECT_EQ(c.idleSeconds, 30);
  // "2#three" is a value, not "2" and a comment: a bad number, warned and the default kept.
  ASSERT_EQ(w.size(), 1u);
  EXPECT_EQ(w[0].rfind("k.conf:6: threads", 0), 0u) << w[0];
  EXPECT_EQ(c.threads, 0);
}

TEST(KioskConfig, StartIsForgivingTheCheckIsStrict) {
  const std::string text =
      "display = vga\n"          // 1: bad value
      "size = 640x480\n"         // 2: fine
      "frobnicate = 1\n"         // 3: unknown key
      "metal = brass\n"          // 4: fine ...
      "metal = silver\n";        // 5: ... set again
  std::vector<std::string> w;
  const KioskConfig c = parse(text, w);
  EXPECT_EQ(c.display, "auto") << "a bad value keeps the default at start";
  EXPECT_EQ(c.width, 640);
  EXPECT_EQ(c.metal, "silver") << "the last one wins";
  EXPECT_EQ(w.size(), 2u);

  const auto problems = checkKioskConfig(text, "k.conf");
  ASSERT_EQ(problems.size(), 3u);
  EXPECT_EQ(problems[0].rfind("k.conf:1: display must be", 0), 0u) << problems[0];
  EXPECT_EQ(problems[1].rfind("k.conf:3: unknown key 'frobnicate'", 0), 0u) << problems[1];
  EXPECT_EQ(problems[2].rfind("k.conf:5: metal is set again (first on line 4)", 0), 0u) << problems[2];
}

TEST(KioskConfig, CheckNamesFilesThatDoNotExist) {
  const fs::path dir = fs::temp_directory_path() / ("emboss-config-test-" + std::to_string(::getpid()));
  fs::create_directories(dir / "pieces");
  std::ofstream(dir / "buttons.json") << "{}";
  const std::string good = "buttons = " + (dir / "buttons.json").string() + "\npieces_dir = " + (dir / "pieces").string() +
                           "\ntablet = auto\ncamera = none\n";
  EXPECT_TRUE(checkKioskConfig(good, "k.conf").empty());

  const std::string bad = "# header\nbuttons = " + (dir / "nope.json").string() +
                          "\ntablet = evemu:" + (dir / "none.events").string() +
                          "\ncamera = file:" + (dir / "none.png").string() +
                          "\npieces_dir = " + (dir / "gone").string() + "\n";
  const auto problems = checkKioskConfig(bad, "k.conf");
  ASSERT_EQ(problems.size(), 4u);
  EXPECT_EQ(problems[0], "k.conf:2: buttons: the buttons file " + (dir / "nope.json").string() + " does not exist");
  EXPECT_EQ(problems[1].rfind("k.conf:3: tablet: the recording", 0), 0u) << problems[1];
  EXPECT_EQ(problems[2].rfind("k.conf:4: camera: the picture", 0), 0u) << problems[2];
  EXPECT_EQ(problems[3].rfind("k.conf:5: pieces_dir: the folder", 0), 0u) << problems[3];
  fs::remove_all(dir);
}

TEST(KioskConfig, ShippedConfigPassesTheCheck) {
  const auto problems = checkKioskConfigFile(fs::path(EMBOSS_SOURCE_DIR) / "firmware-app" / "kiosk.conf");
  EXPECT_TRUE(problems.empty()) << problems.front();
}

TEST(KioskConfig, UnreadableFileIsOneProblem) {
  const auto problems = checkKioskConfigFile("/nonexistent/kiosk.conf");
  ASSERT_EQ(problems.size(), 1u);
  EXPECT_EQ(problems[0].rfind("/nonexistent/kiosk.conf: cannot read the config", 0), 0u) << problems[0];
}

}  // namespace
}  // namespace emboss
