// Tests for finding the sheet: rotated sheets, distractions, and photos that must not yield a sheet.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "capture/homography.h"
#include "capture/sheet.h"

namespace emboss {
namespace {

// A photo: a gray table, optional bright discs, and a white quadrilateral (when given).
struct Scene {
  int width = 800, height = 600;
  std::vector<Vec2> sheet;  // corners, any order around
  struct Disc {
    Vec2 c;
    double r;
  };
  std::vector<Disc> discs;

  bool inSheet(Vec2 p) const {
    if (sheet.size() != 4) return false;
    int pos = 0, neg = 0;
    for (int i = 0; i < 4; ++i) {
      const Vec2 a = sheet[i], b = sheet[(i + 1) % 4];
      const double z = (b.x - a.x) * (p.y - a.y) - (b.y - a.y) * (p.x - a.x);
      pos += z > 0, neg += z < 0;
    }
    return pos == 0 || neg == 0;
  }

  Image render() const {
    Image img(width, height);
    std::mt19937 rng(99);
    std::normal_distribution<double> noise(0, 4);
    for (int y = 0; y < height; ++y)
      for (int x = 0; x < width; ++x) {
        double v = 0;
        for (int s = 0; s < 4; ++s) {
          const Vec2 p{x + 0.25 + 0.5 * (s % 2), y + 0.25 + 0.5 * (s / 2)};
          double c = 70;
          for (const auto& d : discs)
            if (std::hypot(p.x - d.c.x, p.y - d.c.y) <= d.r) c = 235;
          if (inSheet(p)) c = 225;
          v += c / 4;
        }
        v = v * (0.7 + 0.3 * x / width) + noise(rng);
        std::uint8_t* px = img.pixel(x, y);
        px[0] = px[1] = px[2] = static_cast<std::uint8_t>(std::clamp(std::lround(v), 0L, 255L));
        px[3] = 255;
      }
    return img;
  }
};

// The largest distance from each expected corner to the nearest found corner.
double cornerError(const Sheet& s, const std::vector<Vec2>& want) {
  double worst = 0;
  for (const auto& w : want) {
    double best = 1e9;
    for (const auto& c : s.corners) best = std::min(best, std::hypot(c.x - w.x, c.y - w.y));
    worst = std::max(worst, best);
  }
  return worst;
}

TEST(SheetFinder, FindsASheetTurnedFortyDegrees) {
  Scene scene;
  const Vec2 c{400, 300};
  for (int i = 0; i < 4; ++i) {
    const double a = (40 + 90 * i) * M_PI / 180, r = i % 2 ? 200 : 230;  // not a square: a slight trapezoid
    scene.sheet.push_back({c.x + r * std::cos(a), c.y + r * std::sin(a)});
  }
  auto s = findSheet(scene.render());
  ASSERT_TRUE(s) << s.error();
  EXPECT_LT(cornerError(*s, scene.sheet), 1.5);
  // Ordered around the sheet, the first one nearest the photo's top-left.
  for (int i = 1; i < 4; ++i) EXPECT_LE(s->corners[0].x + s->corners[0].y, s->corners[i].x + s->corners[i].y + 1e-9);
}

TEST(SheetFinder, IgnoresABrighterDiscBesideTheSheet) {
  Scene scene;
  scene.sheet = {{60, 80}, {420, 100}, {400, 520}, {80, 500}};
  scene.discs = {{{620, 300}, 120}};
  auto s = findSheet(scene.render());
  ASSERT_TRUE(s) << s.error();
  EXPECT_LT(cornerError(*s, scene.sheet), 1.5);
}

TEST(SheetFinder, ABrightDiscAloneIsNoSheet) {
  Scene scene;
  scene.discs = {{{400, 300}, 200}};
  auto s = findSheet(scene.render());
  ASSERT_FALSE(s);
  EXPECT_NE(s.error().find("no sheet of paper found"), std::string::npos) << s.error();
}

TEST(SheetFinder, ASheetCutByThePhotosEdgeIsRefused) {
  Scene scene;
  scene.sheet = {{-80, 100}, {500, 90}, {520, 520}, {-60, 500}};
  auto s = findSheet(scene.render());
  ASSERT_FALSE(s) << "found corners " << s->corners[0].x << "," << s->corners[0].y << " " << s->corners[1].x << "," << s->corners[1].y << " "
                  << s->corners[2].x << "," << s->corners[2].y << " " << s->corners[3].x << "," << s->corners[3].y;
  EXPECT_NE(s.error().find("all four corners in view"), std::string::npos) << s.error();
}

TEST(SheetFinder, ATinyPhotoFailsClearly) {
  auto s = findSheet(Image(8, 8));
  ASSERT_FALSE(s);
  EXPECT_NE(s.error().find("no sheet of paper found"), std::string::npos) << s.error();
}

}  // namespace
}  // namespace emboss
