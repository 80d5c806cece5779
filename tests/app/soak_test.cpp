// The kiosk's soak (src/bench/soak.h) on a short run: it drives the kiosk through visitors,
// restores and attract cycles and reads the process's memory and descriptors.
#include "bench/soak.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <string>

#include "test_support.h"

namespace emboss {
namespace {

// Runs the soak with what it prints (the table and the verdict) into `text`.
SoakResult runSoakInto(const SoakOptions& o, std::string& text) {
  std::FILE* out = std::tmpfile();
  if (!out) {
    ADD_FAILURE() << "no temporary file";
    return {};
  }
  const SoakResult r = runSoak(o, out);
  std::rewind(out);
  for (int c; (c = std::fgetc(out)) != EOF;) text += char(c);
  std::fclose(out);
  return r;
}

TEST(KioskSoakSlow, AShortRunKeepsItsDescriptorsAndBringsEveryRestoreBack) {
  SoakOptions o;
  o.strokes = 400;
  o.warmup = 100;
  o.attractEvery = 2;
  o.attractSeconds = 1;
  o.dir = test::scratchDir("soak");
  std::string text;
  const SoakResult r = runSoakInto(o, text);
  EXPECT_EQ(r.fdGrowth, 0) << text;
  EXPECT_NE(text.find("| 400 |"), std::string::npos) << text;  // the last row
  EXPECT_NE(text.find("restores: 1, each with every stroke back: PASS"), std::string::npos) << text;
  EXPECT_GT(residentKib(), 0);
  EXPECT_GE(peakResidentKib(), residentKib());
  EXPECT_GT(openFds(), 2);  // stdin, stdout, stderr at least
}

// The verdict's rule catches a leak: 1 MiB held after every visitor (about ten visitors between the
// first window and the last) fails it, while the descriptors still pass.
TEST(KioskSoakSlow, TheVerdictCatchesALeak) {
  SoakOptions o;
  o.strokes = 2400;
  o.reportEvery = 800;
  o.warmup = 100;
  o.attractEvery = 3;
  o.attractSeconds = 1;
  o.leakKibPerVisitor = 1024;
  o.dir = test::scratchDir("soak-leak");
  std::string text;
  const SoakResult r = runSoakInto(o, text);
  EXPECT_FALSE(r.pass) << text;
  EXPECT_GT(r.settledGrowthMb, 5.0) << text;
  EXPECT_EQ(r.fdGrowth, 0) << text;
  EXPECT_NE(text.find("soak: FAIL"), std::string::npos) << text;
}

}  // namespace
}  // namespace emboss
