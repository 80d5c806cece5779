// Tests for thinning, skeleton tracing and simplification on small drawn masks.
#include <gtest/gtest.h>

#include <cmath>

#include "capture/skeleton.h"

namespace emboss {
namespace {

double segDist(Vec2 p, Vec2 a, Vec2 b) {
  const double dx = b.x - a.x, dy = b.y - a.y, l2 = dx * dx + dy * dy;
  const double t = std::clamp(l2 > 0 ? ((p.x - a.x) * dx + (p.y - a.y) * dy) / l2 : 0.0, 0.0, 1.0);
  return std::hypot(p.x - a.x - t * dx, p.y - a.y - t * dy);
}

// Sets the pixels whose centres lie within width / 2 of the segment a-b.
void stroke(Mask& m, Vec2 a, Vec2 b, double width) {
  for (int y = 0; y < m.height; ++y)
    for (int x = 0; x < m.width; ++x)
      if (segDist({x + 0.5, y + 0.5}, a, b) <= width / 2) m.at(x, y) = 1;
}

std::vector<SkeletonPath> traceMask(Mask m, double width) {
  thinZhangSuen(m);
  TraceOptions o;
  o.strokeWidth = width;
  o.spurLength = 1.5 * width;
  return traceSkeleton(m, o);
}

bool closed(const std::vector<Vec2>& p) { return p.front().x == p.back().x && p.front().y == p.back().y; }

TEST(Skeleton, ThinningLeavesOnePixelWideLines) {
  Mask m(80, 30);
  stroke(m, {10, 15}, {70, 15}, 7);
  thinZhangSuen(m);
  for (int x = 15; x < 65; ++x) {
    int n = 0;
    for (int y = 0; y < m.height; ++y) n += m.at(x, y);
    EXPECT_EQ(n, 1) << "column " << x;
  }
}

TEST(Skeleton, ABarIsOneOpenPath) {
  Mask m(80, 30);
  stroke(m, {10, 15}, {70, 15}, 7);
  const auto paths = traceMask(m, 7);
  ASSERT_EQ(paths.size(), 1u);
  EXPECT_FALSE(paths[0].closed);
  EXPECT_GT(polylineLength(paths[0].points), 50.0);
  for (const auto& p : paths[0].points) EXPECT_NEAR(p.y, 15.0, 1.0);
}

TEST(Skeleton, ARingIsOneClosedPath) {
  Mask m(80, 80);
  for (int y = 0; y < 80; ++y)
    for (int x = 0; x < 80; ++x) {
      const double r = std::hypot(x + 0.5 - 40, y + 0.5 - 40);
      m.at(x, y) = std::fabs(r - 25) <= 3;
    }
  const auto paths = traceMask(m, 6);
  ASSERT_EQ(paths.size(), 1u);
  EXPECT_TRUE(paths[0].closed);
  EXPECT_TRUE(closed(paths[0].points));
  for (const auto& p : paths[0].points) EXPECT_NEAR(std::hypot(p.x - 40, p.y - 40), 25.0, 1.0);
}

TEST(Skeleton, ACrossIsTwoStraightStrokes) {
  Mask m(100, 100);
  stroke(m, {10, 10}, {90, 90}, 6);
  stroke(m, {10, 90}, {90, 10}, 6);
  const auto paths = traceMask(m, 6);
  ASSERT_EQ(paths.size(), 2u);
  for (const auto& path : paths) {
    const auto s = simplifyRdp(path.points, 1.0);
    EXPECT_EQ(s.size(), 2u) << "a crossing stroke goes straight through";
  }
}

TEST(Skeleton, ATeeIsTheBarAndTheStem) {
  Mask m(100, 80);
  stroke(m, {10, 15}, {90, 15}, 6);
  stroke(m, {50, 15}, {50, 70}, 6);
  const auto paths = traceMask(m, 6);
  ASSERT_EQ(paths.size(), 2u);
  double longest = 0;
  for (const auto& p : paths) longest = std::max(longest, polylineLength(p.points));
  EXPECT_GT(longest, 70.0);  // the bar, straight through the junction
}

TEST(Skeleton, ASharpCornerIsRebuiltAtTheApex) {
  // A V with a 30-degree opening: thinning forks well before the apex.
  Mask m(120, 120);
  const Vec2 apex{60, 105}, left{60 - 80 * std::sin(M_PI / 12), 105 - 80 * std::cos(M_PI / 12)}, right{60 + 80 * std::sin(M_PI / 12), left.y};
  stroke(m, left, apex, 6);
  stroke(m, apex, right, 6);
  const auto paths = traceMask(m, 6);
  ASSERT_EQ(paths.size(), 1u);
  const auto s = simplifyRdp(paths[0].points, 1.0);
  ASSERT_EQ(s.size(), 3u);
  EXPECT_NEAR(s[1].x, apex.x, 1.5);
  EXPECT_NEAR(s[1].y, apex.y, 1.5);
}

TEST(Skeleton, SpecksAreDropped) {
  Mask m(40, 40);
  m.at(10, 10) = 1;
  m.at(11, 10) = 1;
  m.at(30, 30) = 1;
  EXPECT_TRUE(traceMask(m, 3).empty());
}

TEST(Simplify, AStraightWobblyLineBecomesTwoPoints) {
  std::vector<Vec2> p;
  for (int i = 0; i <= 100; ++i) p.push_back({double(i), i == 0 || i == 100 ? 0.0 : (i % 2) ? 0.4 : -0.4});
  const auto s = simplifyRdp(p, 0.5);
  ASSERT_EQ(s.size(), 2u);
  EXPECT_EQ(s.front().x, 0.0);
  EXPECT_EQ(s.back().x, 100.0);
}

TEST(Simplify, AClosedSquareKeepsItsCornersAndStaysClosed) {
  std::vector<Vec2> p;
  const Vec2 c[5] = {{0, 0}, {10, 0}, {10, 10}, {0, 10}, {0, 0}};
  for (int k = 0; k < 4; ++k)
    for (int i = 0; i < 10; ++i) p.push_back({c[k].x + (c[k + 1].x - c[k].x) * i / 10, c[k].y + (c[k + 1].y - c[k].y) * i / 10});
  p.push_back(p.front());
  const auto s = simplifyRdp(p, 0.1);
  EXPECT_EQ(s.size(), 5u);
  EXPECT_TRUE(closed(s));
}

}  // namespace
}  // namespace emboss
