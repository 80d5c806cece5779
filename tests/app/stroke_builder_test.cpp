// The stroke in progress: what it hands out early is exactly what the whole stroke makes.
#include <gtest/gtest.h>

#include <cmath>

#include "app/stroke_builder.h"
#include "pieces/piece_art.h"

namespace emboss {
namespace {

std::vector<StrokePoint> wobbly(std::uint64_t seed, int n) {
  std::vector<StrokePoint> s;
  double x = -20 + 10 * art::noise(seed, 0), y = -10 + 10 * art::noise(seed, 1), a = art::noise(seed, 2) * 6.28;
  for (int i = 0; i < n; ++i) {
    a += (art::noise(seed, 10 + i) - 0.5) * 0.6;
    const double step = 0.05 + 0.6 * art::noise(seed, 5000 + i);  // uneven sampling, pauses included
    x += std::cos(a) * step, y += std::sin(a) * step;
    s.push_back({x, y, 0.5, 0.2 + 0.7 * art::noise(seed, 9000 + i)});
  }
  return s;
}

TEST(StrokeBuilder, EveryToolHandsOutOnlyWhatTheWholeStrokeMakes) {
  const Metal metal = *metalByName("copper");
  for (const ToolSpec& tool : toolCatalogue()) {
    for (std::uint64_t seed = 1; seed <= 12; ++seed) {
      const auto pts = wobbly(seed * 31 + tool.size * 7, 20 + static_cast<int>(seed * 37));
      StrokeBuilder b;
      b.begin(tool, metal);
      std::vector<Operation> got;
      for (const auto& p : pts)
        for (auto& op : b.add(p)) got.push_back(op);
      const size_t early = got.size();
      const auto f = b.end();
      EXPECT_EQ(f.keep, early) << tool.name << " seed " << seed;
      got.resize(f.keep);
      got.insert(got.end(), f.rest.begin(), f.rest.end());
      const auto want = strokeToOperations(tool, metal, pts);
      ASSERT_EQ(got.size(), want.size()) << tool.name << " seed " << seed;
      for (size_t i = 0; i < want.size(); ++i) EXPECT_TRUE(sameOperation(got[i], want[i])) << tool.name << " op " << i;
      if (tool.kind == ToolKind::Tracer || tool.kind == ToolKind::Punch) {
        EXPECT_GT(early, want.size() / 2) << tool.name << ": the metal should move while the pen does";
      }
      if (tool.kind == ToolKind::RegionRaiser) {
        EXPECT_EQ(early, 0u);
      }
    }
  }
}

TEST(StrokeBuilder, SingleTapIsOneStrike) {
  StrokeBuilder b;
  b.begin(toolCatalogue()[4], *metalByName("brass"));
  EXPECT_TRUE(b.add({1, 2, 0.5, 0.6}).empty());
  const auto f = b.end();
  ASSERT_EQ(f.rest.size(), 1u);
  EXPECT_EQ(f.rest[0].kind, OpKind::Punch);
  EXPECT_DOUBLE_EQ(f.rest[0].at.x, 1.0);
  EXPECT_FALSE(b.active());
}

TEST(StrokeBuilder, SameOperationComparesTheKindsParameters) {
  Operation a;
  a.kind = OpKind::Punch;
  a.at = {1, 2, 3};
  Operation b = a;
  EXPECT_TRUE(sameOperation(a, b));
  b.at.y = 2.5;
  EXPECT_FALSE(sameOperation(a, b));
  b = a;
  b.points = {{9, 9}};  // not a punch's parameter
  EXPECT_TRUE(sameOperation(a, b));
}

}  // namespace
}  // namespace emboss
