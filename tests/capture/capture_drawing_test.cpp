// Tests for capture drawing on synthetic photos: a circle and a zigzag on a sheet in perspective, uneven light, noise.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <random>

#include "capture/capture_drawing.h"
#include "capture/homography.h"
#include "capture/sheet.h"
#include "capture/skeleton.h"
#include "test_support.h"
#include "tools/tool_catalogue.h"

namespace emboss {
namespace {

double segDist(Vec2 p, Vec2 a, Vec2 b) {
  const double dx = b.x - a.x, dy = b.y - a.y, l2 = dx * dx + dy * dy;
  const double t = std::clamp(l2 > 0 ? ((p.x - a.x) * dx + (p.y - a.y) * dy) / l2 : 0.0, 0.0, 1.0);
  return std::hypot(p.x - a.x - t * dx, p.y - a.y - t * dy);
}

// A drawing on an A4 sheet (landscape, mm, y down on the paper) photographed in perspective.
struct SyntheticPhoto {
  int width = 1280, height = 960;
  std::array<Vec2, 4> corners{{{300, 170}, {1060, 235}, {1005, 800}, {215, 735}}};  // TL TR BR BL, photo px
  double paperW = 297, paperH = 210;
  Vec2 circleCentre{85, 105};
  double circleR = 55;
  std::vector<Vec2> zigzag{{170, 50}, {192, 160}, {214, 50}, {236, 160}, {258, 50}, {280, 160}};
  double strokeMm = 1.6;
  double lightLeft = 0.55, lightRight = 1.0;  // the light falls off to the left
  double noise = 5.0;
  bool drawing = true;
  bool paper = true;

  double strokeDistance(Vec2 q) const {
    double d = std::fabs(std::hypot(q.x - circleCentre.x, q.y - circleCentre.y) - circleR);
    for (size_t i = 1; i < zigzag.size(); ++i) d = std::min(d, segDist(q, zigzag[i - 1], zigzag[i]));
    return d;
  }

  Image render() const {
    const auto toPhoto = Homography::fromQuad({Vec2{0, 0}, Vec2{paperW, 0}, Vec2{paperW, paperH}, Vec2{0, paperH}}, corners);
    const auto toPaper = toPhoto->inverse();
    Image img(width, height);
    std::mt19937 rng(1234);
    std::normal_distribution<double> gauss(0.0, noise);
    constexpr int kSub = 3;
    for (int y = 0; y < height; ++y)
      for (int x = 0; x < width; ++x) {
        double rgb[3] = {0, 0, 0};
        for (int sy = 0; sy < kSub; ++sy)
          for (int sx = 0; sx < kSub; ++sx) {
            const Vec2 p{x + (sx + 0.5) / kSub, y + (sy + 0.5) / kSub};
            const Vec2 q = toPaper->apply(p);
            double c[3];
            if (paper && q.x >= 0 && q.y >= 0 && q.x <= paperW && q.y <= paperH) {
              const bool ink = drawing && strokeDistance(q) <= strokeMm / 2;
              const double v = ink ? 38 : 232;
              c[0] = v, c[1] = v * 0.98, c[2] = v * (ink ? 1.05 : 0.93);
            } else {  // a darker wooden table with some grain
              const double grain = 8 * std::sin(p.y * 0.21 + 3 * std::sin(p.x * 0.013)) + 4 * std::sin(p.x * 0.05 + p.y * 0.011);
              const double v = 78 + grain;
              c[0] = v * 1.15, c[1] = v * 0.92, c[2] = v * 0.7;
            }
            for (int k = 0; k < 3; ++k) rgb[k] += c[k] / (kSub * kSub);
          }
        const double fx = double(x) / width, fy = double(y) / height - 0.5;
        const double light = (lightLeft + (lightRight - lightLeft) * fx) * (1.0 - 0.6 * fy * fy);
        std::uint8_t* px = img.pixel(x, y);
        for (int k = 0; k < 3; ++k) px[k] = static_cast<std::uint8_t>(std::clamp(std::lround(rgb[k] * light + gauss(rng)), 0L, 255L));
        px[3] = 255;
      }
    return img;
  }

  // Where a paper point lands on a plateW x plateH plate (margin 5 mm, aspect kept, centred, y up).
  Vec2 paperToPlate(Vec2 q, double plateW, double plateH, double margin = 5.0) const {
    const double s = std::min((plateW - 2 * margin) / paperW, (plateH - 2 * margin) / paperH);
    return {(q.x - paperW / 2) * s, (paperH / 2 - q.y) * s};
  }
};

// Where to write the pictures for a person to look at: EMBOSS_CAPTURE_DUMP, else the build tree.
std::filesystem::path dumpDir() {
  if (const char* d = std::getenv("EMBOSS_CAPTURE_DUMP")) return d;
  return test::scratchDir("capture");
}

// Distance from p to the nearest point of a set of polylines.
double distanceToPolylines(Vec2 p, const std::vector<std::vector<Vec2>>& lines) {
  double d = 1e9;
  for (const auto& l : lines)
    for (size_t i = 1; i < l.size(); ++i) d = std::min(d, segDist(p, l[i - 1], l[i]));
  return d;
}

// Points every `step` along a polyline.
std::vector<Vec2> densify(const std::vector<Vec2>& l, double step) {
  std::vector<Vec2> out;
  for (size_t i = 1; i < l.size(); ++i) {
    const double len = std::hypot(l[i].x - l[i - 1].x, l[i].y - l[i - 1].y);
    const int n = std::max(1, static_cast<int>(std::ceil(len / step)));
    for (int k = 0; k < n; ++k) out.push_back({l[i - 1].x + (l[i].x - l[i - 1].x) * k / n, l[i - 1].y + (l[i].y - l[i - 1].y) * k / n});
  }
  if (!l.empty()) out.push_back(l.back());
  return out;
}

// The guide over a light plate with the traced polylines in red, their vertices in blue: for a person.
Image tracedOverlay(const CaptureResult& r) {
  Image img = r.guide;
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      std::uint8_t* p = img.pixel(x, y);
      const double a = p[3] / 255.0;
      for (int k = 0; k < 3; ++k) p[k] = static_cast<std::uint8_t>(std::lround(a * p[k] + (1 - a) * 225));
      p[3] = 255;
    }
  auto plot = [&](Vec2 g, std::uint8_t r8, std::uint8_t g8, std::uint8_t b8, int radius) {
    for (int dy = -radius; dy <= radius; ++dy)
      for (int dx = -radius; dx <= radius; ++dx) {
        const int x = static_cast<int>(g.x) + dx, y = static_cast<int>(g.y) + dy;
        if (x < 0 || y < 0 || x >= img.width || y >= img.height) continue;
        std::uint8_t* p = img.pixel(x, y);
        p[0] = r8, p[1] = g8, p[2] = b8;
      }
  };
  for (const auto& l : r.polylines) {
    for (const auto& p : densify(l, 0.05)) plot(r.mapping.plateToGuide(p), 230, 30, 30, 0);
    for (const auto& p : l) plot(r.mapping.plateToGuide(p), 30, 60, 230, 1);
  }
  return img;
}

class CaptureDrawing : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    photo_ = new Image(SyntheticPhoto{}.render());
    (void)writePng(*photo_, dumpDir() / "capture_photo.png");
  }
  static void TearDownTestSuite() {
    delete photo_;
    photo_ = nullptr;
  }
  static Image* photo_;
};
Image* CaptureDrawing::photo_ = nullptr;

TEST_F(CaptureDrawing, FindsTheSheetsCornersWithinAPixel) {
  const SyntheticPhoto scene;
  auto sheet = findSheet(*photo_);
  ASSERT_TRUE(sheet) << sheet.error();
  double worst = 0;
  for (int i = 0; i < 4; ++i) {
    const double e = std::hypot(sheet->corners[i].x - scene.corners[i].x, sheet->corners[i].y - scene.corners[i].y);
    worst = std::max(worst, e);
    EXPECT_LT(e, 1.5) << "corner " << i << " at " << sheet->corners[i].x << ", " << sheet->corners[i].y;
  }
  RecordProperty("worst_corner_error_px", std::to_string(worst));
  std::printf("corner error: worst %.3f px; edge support %.2f, contrast %.2f\n", worst, sheet->edgeSupport, sheet->contrast);
  EXPECT_GT(sheet->edgeSupport, 0.9);
}

TEST_F(CaptureDrawing, TracesTheCircleAndTheZigzagWithinAMillimetre) {
  const SyntheticPhoto scene;
  constexpr double kPlateW = 200, kPlateH = 150;
  auto r = captureDrawing(*photo_, kPlateW, kPlateH);
  ASSERT_TRUE(r) << r.error();
  (void)writePng(r->guide, dumpDir() / "capture_guide.png");
  (void)writePng(r->paper, dumpDir() / "capture_paper.png");
  (void)writePng(tracedOverlay(*r), dumpDir() / "capture_traced.png");

  // Two strokes: the circle closed, the zigzag open.
  std::string strokes;
  for (const auto& l : r->polylines)
    strokes += std::to_string(l.size()) + " points, " + std::to_string(polylineLength(l)) + " mm from " + std::to_string(l.front().x) + "," +
               std::to_string(l.front().y) + " to " + std::to_string(l.back().x) + "," + std::to_string(l.back().y) + "\n";
  ASSERT_EQ(r->polylines.size(), 2u) << strokes;
  int closed = 0;
  for (const auto& l : r->polylines) closed += l.front().x == l.back().x && l.front().y == l.back().y;
  EXPECT_EQ(closed, 1);

  // The known strokes on the plate.
  std::vector<std::vector<Vec2>> truth(2);
  for (int i = 0; i <= 720; ++i) {
    const double a = 2 * M_PI * i / 720;
    truth[0].push_back(scene.paperToPlate({scene.circleCentre.x + scene.circleR * std::cos(a), scene.circleCentre.y + scene.circleR * std::sin(a)}, kPlateW, kPlateH));
  }
  for (const auto& p : scene.zigzag) truth[1].push_back(scene.paperToPlate(p, kPlateW, kPlateH));

  // Every traced point lies on a known stroke...
  double worst = 0, sum = 0;
  int n = 0;
  for (const auto& l : r->polylines)
    for (const auto& p : densify(l, 0.25)) {
      const double d = distanceToPolylines(p, truth);
      worst = std::max(worst, d), sum += d, ++n;
    }
  // ...and every known stroke point has a traced point near it.
  double worstCover = 0;
  for (const auto& l : truth)
    for (const auto& p : densify(l, 0.5)) worstCover = std::max(worstCover, distanceToPolylines(p, r->polylines));
  std::printf("traced: %zu strokes, %zu points; off the strokes: mean %.3f mm, worst %.3f mm; strokes uncovered by at most %.3f mm; width %.2f mm\n",
              r->polylines.size(), r->polylines[0].size() + r->polylines[1].size(), sum / n, worst, worstCover, r->strokeWidthMm);
  EXPECT_LT(worst, 1.0);
  EXPECT_LT(sum / n, 0.3);
  EXPECT_LT(worstCover, 1.0);

  // The operations: front traces of at most kTraceSegment mm, valid, on the plate.
  ASSERT_FALSE(r->operations.empty());
  for (const auto& op : r->operations) {
    EXPECT_EQ(op.kind, OpKind::Trace);
    EXPECT_EQ(op.side, Side::Front);
    EXPECT_EQ(validate(op), "");
    EXPECT_LE(polylineLength(op.points), kTraceSegment + 1e-9);
    for (const auto& p : op.points) {
      EXPECT_LE(std::fabs(p.x), kPlateW / 2);
      EXPECT_LE(std::fabs(p.y), kPlateH / 2);
    }
  }
  double opsLength = 0, linesLength = 0;
  for (const auto& op : r->operations) opsLength += polylineLength(op.points);
  for (const auto& l : r->polylines) linesLength += polylineLength(l);
  EXPECT_NEAR(opsLength, linesLength, 1e-6);

  // The guide is the plate: ink opaque where the circle passes, transparent at the plate's centre of the circle.
  EXPECT_EQ(r->guide.width, 800);
  EXPECT_EQ(r->guide.height, 600);
  const Vec2 onCircle = r->mapping.plateToGuide(truth[0][0]);
  const Vec2 inCircle = r->mapping.plateToGuide(scene.paperToPlate(scene.circleCentre, kPlateW, kPlateH));
  EXPECT_GT(r->guide.pixel(int(onCircle.x), int(onCircle.y))[3], 200);
  EXPECT_EQ(r->guide.pixel(int(inCircle.x), int(inCircle.y))[3], 0);
  // The mapping takes the photo's corners of the sheet to the paper's rectangle on the plate.
  const Vec2 tl = r->mapping.photoToPlate(scene.corners[0]), want = scene.paperToPlate({0, 0}, kPlateW, kPlateH);
  EXPECT_NEAR(tl.x, want.x, 0.5);
  EXPECT_NEAR(tl.y, want.y, 0.5);
}

TEST_F(CaptureDrawing, StrongerSideLightStillWorks) {
  SyntheticPhoto scene;
  scene.lightLeft = 0.2;  // the sheet's dim end (gray 78) is darker than the table's lit end (up to 85)
  scene.noise = 7;
  const Image photo = scene.render();
  (void)writePng(photo, dumpDir() / "capture_photo_dim.png");
  auto r = captureDrawing(photo, 200, 150);
  ASSERT_TRUE(r) << r.error();
  double worst = 0;
  for (int i = 0; i < 4; ++i) worst = std::max(worst, std::hypot(r->corners[i].x - scene.corners[i].x, r->corners[i].y - scene.corners[i].y));
  std::printf("dim light: worst corner error %.3f px, %zu strokes\n", worst, r->polylines.size());
  EXPECT_LT(worst, 2.0);
  EXPECT_EQ(r->polylines.size(), 2u);
}

TEST(CaptureDrawingFailures, APhotoWithoutPaperFailsWithTheMessage) {
  SyntheticPhoto scene;
  scene.paper = false;
  auto r = captureDrawing(scene.render(), 200, 150);
  ASSERT_FALSE(r);
  EXPECT_NE(r.error().find("no sheet of paper found"), std::string::npos) << r.error();
}

TEST(CaptureDrawingFailures, AnEmptySheetHasNoDrawing) {
  SyntheticPhoto scene;
  scene.drawing = false;
  auto r = captureDrawing(scene.render(), 200, 150);
  ASSERT_FALSE(r);
  EXPECT_NE(r.error().find("no drawing found"), std::string::npos) << r.error();
}

TEST(CaptureDrawingFailures, AnUnknownTracerIsNamed) {
  CaptureOptions o;
  o.tracer = "Punch";
  auto ops = traceOperations({{{0, 0}, {1, 0}}}, o);
  ASSERT_FALSE(ops);
  EXPECT_NE(ops.error().find("no tracer named 'Punch'"), std::string::npos) << ops.error();
}

TEST(CaptureTraceOperations, SplitsLongStrokesAtTheSegmentLength) {
  auto ops = traceOperations({{{0, 0}, {10, 0}, {10, 3}}}, CaptureOptions{});
  ASSERT_TRUE(ops) << ops.error();
  ASSERT_EQ(ops->size(), 4u);  // 13 mm: 4 + 4 + 4 + 1
  EXPECT_NEAR((*ops)[0].points.back().x, 4.0, 1e-9);
  EXPECT_NEAR((*ops)[2].points.front().x, 8.0, 1e-9);
  EXPECT_EQ((*ops)[2].points.size(), 3u);  // 8,0 -> 10,0 -> 10,2
  EXPECT_NEAR((*ops)[3].points.back().y, 3.0, 1e-9);
  for (size_t i = 1; i < ops->size(); ++i) {
    EXPECT_EQ((*ops)[i].points.front().x, (*ops)[i - 1].points.back().x);
    EXPECT_EQ((*ops)[i].points.front().y, (*ops)[i - 1].points.back().y);
  }
}

}  // namespace
}  // namespace emboss
