// Pixel spans: the pixels near convex outlines, grown and united.
#include <gtest/gtest.h>

#include <vector>

#include "render/pixel_spans.h"

namespace emboss {
namespace {

TEST(PixelSpans, ARectangleIsEveryPixelOfIt) {
  const PixelSpans s = PixelSpans::of({3, 4, 5, 2});
  EXPECT_EQ(s.area(), 10);
  EXPECT_TRUE(s.contains(3, 4));
  EXPECT_TRUE(s.contains(7, 5));
  EXPECT_FALSE(s.contains(8, 5));
  EXPECT_FALSE(s.contains(3, 6));
  EXPECT_TRUE(PixelSpans::of({0, 0, 0, 3}).empty());
}

TEST(PixelSpans, GrowingAPixelGivesItsNeighboursWithinTheImage) {
  const PixelSpans one = PixelSpans::of({5, 5, 1, 1});
  const PixelSpans g = one.grown(1, 100, 100);
  EXPECT_EQ(g.box.x, 4);
  EXPECT_EQ(g.box.y, 4);
  EXPECT_EQ(g.area(), 9);
  const PixelSpans corner = PixelSpans::of({0, 0, 1, 1}).grown(2, 100, 100);
  EXPECT_EQ(corner.area(), 9) << "clipped to the image";
  EXPECT_EQ(corner.box.x, 0);
}

TEST(PixelSpans, UnitingKeepsBoth) {
  const PixelSpans a = PixelSpans::of({0, 0, 2, 2}), b = PixelSpans::of({10, 1, 2, 3});
  const PixelSpans u = a.united(b);
  EXPECT_EQ(u.box.y, 0);
  EXPECT_EQ(u.box.h, 4);
  EXPECT_TRUE(u.contains(0, 0));
  EXPECT_TRUE(u.contains(11, 3));
  EXPECT_TRUE(u.contains(5, 1)) << "a row is the hull of both spans";
  EXPECT_FALSE(u.contains(5, 0));
  EXPECT_EQ(u.area(), 2 + 12 + 2 + 2);  // rows 0: a; 1: from a to b; 2 and 3: b
}

TEST(PixelSpans, ABandIsItsRowsTrimmed) {
  PixelSpans s = PixelSpans::of({0, 10, 5, 4});
  s.rows[1] = {};  // row 11 empty
  const PixelSpans b = s.band(11, 13);
  EXPECT_EQ(b.box.y, 12) << "the empty row at the top is trimmed";
  EXPECT_EQ(b.box.h, 1);
  EXPECT_EQ(b.area(), 5);
  EXPECT_TRUE(s.band(0, 10).empty());
  EXPECT_EQ(s.band(0, 100).area(), 15);
}

TEST(PixelSpans, ASplitTakesWholeRowsThenTheLeftOfTheNext) {
  PixelSpans s = PixelSpans::of({3, 10, 5, 4});
  s.rows[1] = {};      // row 11 empty
  s.rows[2] = {4, 6};  // row 12: two pixels
  const auto [head, rest] = s.split(8);
  // Row 10 (5 pixels), row 12 (2), then the first pixel of row 13.
  EXPECT_EQ(head.area(), 8);
  EXPECT_EQ(rest.area(), s.area() - 8);
  EXPECT_TRUE(head.contains(3, 13) && !head.contains(4, 13));
  EXPECT_TRUE(rest.contains(4, 13) && !rest.contains(3, 13));
  EXPECT_EQ(rest.box.y, 13) << "the rows left empty are trimmed";
  EXPECT_EQ(rest.box.h, 1);
  EXPECT_EQ(head.box.h, 4);
  for (int y = 10; y < 14; ++y)
    for (int x = 0; x < 12; ++x) EXPECT_EQ(s.contains(x, y), head.contains(x, y) || rest.contains(x, y)) << x << "," << y;
  EXPECT_TRUE(s.split(0).first.empty());
  EXPECT_EQ(s.split(0).second.area(), s.area());
  EXPECT_EQ(s.split(100).first.area(), s.area());
  EXPECT_TRUE(s.split(100).second.empty());
}

TEST(PixelSpans, AHullKeepsThePixelsWithinAPixelOfIt) {
  SpanBuilder b(100, 100);
  const std::vector<glm::dvec2> square{{10, 5}, {20, 5}, {20, 15}, {10, 15}, {15, 10}};
  b.addHullOf(square);
  const PixelSpans s = b.take();
  // Rows whose band [y - 1, y + 2] meets image y 5..15: 3..16; each from a pixel before x = 10
  // to a pixel after x = 20.
  EXPECT_EQ(s.box.y, 3);
  EXPECT_EQ(s.box.y + s.box.h, 17);
  EXPECT_EQ(s.row(10).x0, 9);
  EXPECT_EQ(s.row(10).x1, 21);
  EXPECT_TRUE(s.row(2).empty());
  EXPECT_TRUE(s.row(17).empty());
}

TEST(PixelSpans, ATriangleIsNarrowAtItsApex) {
  SpanBuilder b(200, 200);
  const std::vector<glm::dvec2> tri{{100, 10}, {150, 110}, {50, 110}};
  b.addHullOf(tri);
  const PixelSpans s = b.take();
  const auto near = s.row(12), far = s.row(105);
  EXPECT_LT(near.x1 - near.x0, 12);
  EXPECT_GT(far.x1 - far.x0, 90);
  // Every pixel centre inside the triangle is kept.
  for (int y = 10; y < 110; ++y)
    for (int x = 0; x < 200; ++x) {
      const double px = x + 0.5, py = y + 0.5;
      const double half = (py - 10.0) * 0.5;
      if (py >= 10 && py <= 110 && px >= 100 - half && px <= 100 + half) {
        ASSERT_TRUE(s.contains(x, y)) << x << "," << y;
      }
    }
  // Far from it nothing is.
  EXPECT_FALSE(s.contains(10, 20));
  EXPECT_FALSE(s.contains(190, 20));
  EXPECT_LT(s.area(), s.box.area() * 7 / 10);
}

TEST(PixelSpans, HullsOfSeveralPiecesAddUp) {
  SpanBuilder b(200, 200);
  const std::vector<glm::dvec2> p1{{10, 10}, {20, 10}, {20, 20}, {10, 20}}, p2{{150, 150}, {160, 150}, {160, 160}};
  b.addHullOf(p1);
  b.addHullOf(p2);
  const PixelSpans s = b.take();
  EXPECT_TRUE(s.contains(15, 15));
  EXPECT_TRUE(s.contains(155, 152));
  EXPECT_FALSE(s.contains(15, 100));
  EXPECT_FALSE(s.contains(100, 15));
}

}  // namespace
}  // namespace emboss
