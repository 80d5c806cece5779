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
      if (tool.kind == ToolKind::FlatPunch && want.size() >= 2) {
        // Handed out while the pen moves, all but a strike placed after the builder last looked
        // (it looks again each quarter millimetre the pen moves).
        EXPECT_GE(early + 1, want.size()) << tool.name << " seed " << seed;
      }
    }
  }
}

// The flat punch's strikes: its face (the tool's size across the stroke, 0.7 of it along) lowered
// at points exactly evenly spaced on the stroke, kFlatPunchOverlap to a face's length, each turned
// along the line from the strike a face's length before (the first ones: from the first, or to
// the next). A single tap: one strike, its long side along x, half the penetration depth deep.
TEST(StrokeBuilder, TheFlatPunchsStrikesAreEvenlySpacedAndTurnedAlongTheStroke) {
  const Metal metal = *metalByName("copper");
  ToolSpec tool;
  for (const auto& t : toolCatalogue())
    if (t.kind == ToolKind::FlatPunch) tool = t;
  ASSERT_EQ(tool.kind, ToolKind::FlatPunch);
  const double along = 0.7 * tool.size, across = tool.size, spacing = along / kFlatPunchOverlap;
  const size_t back = kFlatPunchOverlap;
  for (std::uint64_t seed = 1; seed <= 12; ++seed) {
    const auto pts = wobbly(seed * 57, 60 + static_cast<int>(seed * 23));
    const auto ops = strokeToOperations(tool, metal, pts);
    ASSERT_GE(ops.size(), 6u) << "seed " << seed;
    std::vector<Vec2> c;
    for (const auto& op : ops) {
      ASSERT_EQ(op.kind, OpKind::Region);
      EXPECT_EQ(op.side, Side::Front);
      ASSERT_EQ(op.points.size(), 4u);
      EXPECT_DOUBLE_EQ(op.falloff, kFlatPunchFalloff * tool.size);
      EXPECT_GT(op.height, 0.0);
      EXPECT_LT(op.height, 0.5 * penetrationDepth(tool, metal, 1.0) / kFlatPunchOverlap);
      const auto& q = op.points;
      c.push_back({0.25 * (q[0].x + q[1].x + q[2].x + q[3].x), 0.25 * (q[0].y + q[1].y + q[2].y + q[3].y)});
      EXPECT_NEAR(std::hypot(q[1].x - q[0].x, q[1].y - q[0].y), along, 1e-9);
      EXPECT_NEAR(std::hypot(q[2].x - q[1].x, q[2].y - q[1].y), across, 1e-9);
      EXPECT_NEAR(std::hypot(q[2].x - q[0].x, q[2].y - q[0].y), std::hypot(along, across), 1e-9);  // a rectangle
    }
    EXPECT_NEAR(c[0].x, pts[0].x, 1e-9);
    EXPECT_NEAR(c[0].y, pts[0].y, 1e-9);
    for (size_t i = 0; i < ops.size(); ++i) {
      if (i) {
        EXPECT_NEAR(std::hypot(c[i].x - c[i - 1].x, c[i].y - c[i - 1].y), spacing, 1e-9) << "strike " << i;
      }
      const Vec2 a = c[i >= back ? i - back : 0], b = c[std::max<size_t>(i, 1)];
      const auto& q = ops[i].points;
      // The face's short side lies along the line from a to b.
      const double cross = (q[1].x - q[0].x) * (b.y - a.y) - (q[1].y - q[0].y) * (b.x - a.x);
      EXPECT_NEAR(cross, 0.0, 1e-9) << "strike " << i;
    }
  }
  const auto one = strokeToOperations(tool, metal, {{3, 4, 0.5, 0.6}});
  ASSERT_EQ(one.size(), 1u);
  EXPECT_NEAR(std::abs(one[0].points[2].x - one[0].points[1].x), across, 1e-9);
  EXPECT_DOUBLE_EQ(one[0].height, 0.5 * penetrationDepth(tool, metal, 0.6));
}

// The region's descent integrated across, in units of its falloff: atan(3) to 3 F where it is
// exact, and a little more in the taper beyond (between its value at 3 F times nothing and times F).
TEST(StrokeBuilder, TheRegionsDescentIntegratesToAboutOnePointThreeFalloffs) {
  const double exact = std::atan(3.0);
  EXPECT_GT(flatPunchDescent(), exact);
  EXPECT_LT(flatPunchDescent(), exact + 0.1);
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
