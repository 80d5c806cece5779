// Tests for homographies: four point pairs map exactly, inverses and compositions agree, degenerate quads fail.
#include <gtest/gtest.h>

#include <random>

#include "capture/homography.h"

namespace emboss {
namespace {

const std::array<Vec2, 4> kPhoto{{{300, 170}, {1060, 235}, {1005, 800}, {215, 735}}};
const std::array<Vec2, 4> kRect{{{0, 0}, {297, 0}, {297, 210}, {0, 210}}};

TEST(Homography, MapsTheFourCornersExactly) {
  const auto h = Homography::fromQuad(kPhoto, kRect);
  ASSERT_TRUE(h);
  for (int i = 0; i < 4; ++i) {
    const Vec2 p = h->apply(kPhoto[i]);
    EXPECT_NEAR(p.x, kRect[i].x, 1e-9);
    EXPECT_NEAR(p.y, kRect[i].y, 1e-9);
  }
}

TEST(Homography, InverseAndCompositionRoundTrip) {
  const auto h = Homography::fromQuad(kPhoto, kRect);
  ASSERT_TRUE(h);
  const auto inv = h->inverse();
  ASSERT_TRUE(inv);
  const Homography id = *inv * *h;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0, 1200);
  for (int i = 0; i < 100; ++i) {
    const Vec2 p{u(rng), u(rng)};
    const Vec2 q = inv->apply(h->apply(p)), r = id.apply(p);
    EXPECT_NEAR(q.x, p.x, 1e-7);
    EXPECT_NEAR(q.y, p.y, 1e-7);
    EXPECT_NEAR(r.x, p.x, 1e-7);
    EXPECT_NEAR(r.y, p.y, 1e-7);
  }
}

TEST(Homography, StraightLinesStayStraight) {
  const auto h = Homography::fromQuad(kRect, kPhoto);
  ASSERT_TRUE(h);
  // The paper's diagonal, sampled, stays on the photo's diagonal.
  const Vec2 a = h->apply(kRect[0]), b = h->apply(kRect[2]);
  for (double t = 0; t <= 1; t += 0.1) {
    const Vec2 p = h->apply({297 * t, 210 * t});
    const double cross = (b.x - a.x) * (p.y - a.y) - (b.y - a.y) * (p.x - a.x);
    EXPECT_NEAR(cross / std::hypot(b.x - a.x, b.y - a.y), 0.0, 1e-7);
  }
}

TEST(Homography, ThreeCollinearCornersFail) {
  const std::array<Vec2, 4> bad{{{0, 0}, {10, 0}, {20, 0}, {0, 10}}};
  EXPECT_FALSE(Homography::fromQuad(bad, kRect));
}

}  // namespace
}  // namespace emboss
