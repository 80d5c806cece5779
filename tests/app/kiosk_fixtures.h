// What the kiosk's tests share: the screen size, fake buttons, the demo recording, a config in a
// scratch folder and a small attract piece.
#pragma once

#include <gtest/gtest.h>

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "app/kiosk_app.h"
#include "demo_recording.h"
#include "input/evemu.h"

namespace emboss::test {

namespace fs = std::filesystem;
inline constexpr int kW = 480, kH = 300;

inline std::vector<PenSample> demoSamples() {
  auto rec = parseEvemu(test::visitorDemoRecording());
  EXPECT_TRUE(rec) << (rec ? "" : rec.error());
  auto samples = evemuToSamples(*rec);
  EXPECT_TRUE(samples);
  return *samples;
}

inline KioskConfig testConfig(const fs::path& dir) {
  KioskConfig c;
  c.sessionsDir = dir / "sessions";
  c.exportDir = dir / "export";
  c.threads = 2;
  return c;
}

// A small, quick attract piece.
inline std::vector<AttractPiece> tinyPieces() {
  Scene s;
  s.workpiece = std::make_shared<Plate>(30.0, 20.0, 0.5);
  s.title = "tiny";
  for (int i = 0; i < 6; ++i) {
    Operation op;
    op.kind = OpKind::Punch;
    op.a = 3, op.p = 0.2, op.q = 1;
    op.at = {-15.0 + 6 * i, 0, 0.5};
    s.operations.push_back(op);
  }
  return {{"tiny", s}};
}

}  // namespace emboss::test
