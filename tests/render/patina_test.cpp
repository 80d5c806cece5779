// The patina brush: the scene format, a stroke of the kiosk's brush, a colour that moves nothing,
// settles into the hollows, goes with an undo, and reaches the POV-Ray export.
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iomanip>
#include <limits>
#include <random>
#include <span>

#include <gtest/gtest.h>

#include "app/stroke_builder.h"
#include "export/pov.h"
#include "frep/kernels.h"
#include "render/patina_cache.h"
#include "render/renderer.h"
#include "render/shading.h"
#include "scene/scene.h"
#include "test_support.h"
#include "tools/tool_catalogue.h"

namespace emboss {
namespace {

const char* kScene = R"({"format": "emboss-scene", "version": 1, "metal": "copper", "deformation": "sheet",
  "workpiece": {"type": "plate", "w": 20, "h": 14, "d": 0.5},
  "camera": {"type": "perspective", "eye": [0, -20, 60], "target": [0, 0, 0], "up": [0, 1, 0], "fov_deg": 35},
  "operations": [
    {"op": "trace", "side": "front", "a": 0.8, "points": [[-12, 0], [12, 0]]},
    {"op": "patina", "tinge": "black", "points": [[-14, 0], [14, 0]], "r": 4, "strength": 1.0}
  ]})";

// Copper, lit for the model's front face.
ShadingParams copper(const Model& model) {
  ShadingParams s;
  s.metal = *metalByName("copper");
  s.frontZ = model.workpiece().bounds().z1;
  return s;
}

TEST(Patina, SceneFormatReadsAndWritesIt) {
  auto scene = parseScene(kScene, "patina.json", ".");
  ASSERT_TRUE(scene) << scene.error();
  ASSERT_EQ(scene->operations.size(), 2u);
  const Operation& p = scene->operations[1];
  EXPECT_EQ(p.kind, OpKind::Patina);
  EXPECT_EQ(tinges()[static_cast<size_t>(p.tinge)].name, "black");
  EXPECT_EQ(p.a, 4.0);
  EXPECT_EQ(p.strength, 1.0);
  const std::string line = operationToJson(p);
  EXPECT_NE(line.find("\"tinge\":\"black\""), std::string::npos) << line;
  EXPECT_NE(line.find("\"r\":4"), std::string::npos) << line;
  auto again = parseScene(sceneToJson(*scene), "again.json", ".");
  ASSERT_TRUE(again) << again.error();
  EXPECT_EQ(again->operations[1].tinge, p.tinge);
  EXPECT_EQ(again->operations[1].points.size(), p.points.size());
  // Bad values are named.
  for (const auto& [bad, key] : {std::pair{R"("tinge": "purple")", "operations[1].tinge"},
                                 std::pair{R"("tinge": "black", "strength": 1.5)", "operations[1].strength"},
                                 std::pair{R"("tinge": "black", "r": -1)", "operations[1].r"}}) {
    std::string text = kScene;
    const std::string from = R"("tinge": "black")";
    text.replace(text.find(from), from.size(), bad);
    if (std::string(bad).find("\"r\"") != std::string::npos) text.replace(text.find(R"("r": 4, )"), 8, "");
    if (std::string(bad).find("strength") != std::string::npos) text.replace(text.find(R"(, "strength": 1.0)"), 17, "");
    auto s = parseScene(text, "bad.json", ".");
    ASSERT_FALSE(s) << bad;
    EXPECT_NE(s.error().find(key), std::string::npos) << s.error();
  }
}

TEST(Patina, ColoursAndMovesNothing) {
  auto scene = parseScene(kScene, "patina.json", ".");
  ASSERT_TRUE(scene);
  auto with = scene->makeModel();
  Scene bare = *scene;
  bare.operations.pop_back();
  auto without = bare.makeModel();
  ASSERT_TRUE(with && without);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int i = 0; i < 2000; ++i) {
    const P3<double> p{15 * u(rng), 10 * u(rng), 0.6 * u(rng)};
    ASSERT_EQ(with->evaluate(p), without->evaluate(p));
  }
  EXPECT_EQ(with->bounds().z0, without->bounds().z0);
  EXPECT_EQ(with->bounds().z1, without->bounds().z1);
  // The brush: full in its middle, a soft rim, nothing beyond its radius.
  const PreparedOp& op = with->operations()[1];
  EXPECT_DOUBLE_EQ(op.patinaAt(0, 0), 1.0);
  EXPECT_GT(op.patinaAt(0, 2), 0.8);
  EXPECT_GT(op.patinaAt(0, 3.5), 0.0);
  EXPECT_LT(op.patinaAt(0, 3.5), 0.5);
  EXPECT_EQ(op.patinaAt(0, 4.01), 0.0);
}

// A patina stroke of n points wandering so that it crosses itself: steps of up to `step` mm each
// way, and `drift` mm along a heading that turns by `turn` radians a point.
Operation wanderingStroke(std::mt19937& rng, int n, double a, double strength, double step, double drift, double turn) {
  Operation op;
  op.kind = OpKind::Patina;
  op.a = a;
  op.strength = strength;
  std::uniform_real_distribution<double> d(-step, step);
  Vec2 at{0.0, 0.0};
  for (int i = 0; i < n; ++i) {
    op.points.push_back(at);
    at.x += d(rng) + drift * std::cos(i * turn), at.y += d(rng) + drift * std::sin(i * turn);
  }
  return op;
}

// A long stroke: patinaAt() passes the segments whose box grown by the brush's radius does not
// hold the point. Its value must be the brush's profile over the distance to the whole polyline,
// computed here segment by segment in arithmetic of its own (so to 1e-12; the attract pieces'
// pictures were the same bytes before and after the change).
TEST(Patina, ALongStrokeIsTheProfileOfTheDistanceToAllItsSegments) {
  std::mt19937 rng(7);
  const Operation op = wanderingStroke(rng, 300, 2.5, 0.8, 1.5, 0.4, 0.05);
  const PreparedOp prepared(op);
  const Box2 box = prepared.support();
  std::uniform_real_distribution<double> px(box.x0, box.x1), py(box.y0, box.y1);
  int inside = 0;
  for (int k = 0; k < 20000; ++k) {
    const double x = px(rng), y = py(rng);
    double d2 = std::numeric_limits<double>::infinity();
    for (size_t i = 1; i < op.points.size(); ++i) {
      const Vec2 &s = op.points[i - 1], &e = op.points[i];
      const double dx = e.x - s.x, dy = e.y - s.y, len2 = dx * dx + dy * dy;
      const double t = len2 > 0 ? std::clamp(((x - s.x) * dx + (y - s.y) * dy) / len2, 0.0, 1.0) : 0.0;
      d2 = std::min(d2, (x - s.x - t * dx) * (x - s.x - t * dx) + (y - s.y - t * dy) * (y - s.y - t * dy));
    }
    const double u = d2 / (op.a * op.a);
    const double want = u >= 1.0 ? 0.0 : op.strength * (1.0 - u * u) * (1.0 - u * u);
    const double got = prepared.patinaAt(x, y);
    ASSERT_NEAR(got, want, 1e-12) << "at " << x << ", " << y;
    inside += got > 0.0;
  }
  EXPECT_GT(inside, 2000);   // the stroke covers a good part of its box, and not all of it
  EXPECT_LT(inside, 19000);
}

// patinaAt() passes the segments of a long stroke eight at a time when the point lies beyond their
// box grown by the brush's radius: the same bits as testing each segment's box.
TEST(Patina, ALongStrokesSegmentsPassedInChunksGiveTheSameBits) {
  std::mt19937 rng(11);
  const Operation op = wanderingStroke(rng, 203, 1.5, 0.9, 1.0, 0.3, 0.07);  // a last chunk of two segments
  const PreparedOp prepared(op);
  const Box2 box = prepared.support();
  std::uniform_real_distribution<double> px(box.x0, box.x1), py(box.y0, box.y1);
  const double a = op.a, reach2 = a * a;
  int inside = 0;
  for (int k = 0; k < 20000; ++k) {
    // Points on a segment's end now and then (the chunks' edges).
    const Vec2 q = op.points[static_cast<size_t>(k) % op.points.size()];
    const double x = k % 7 == 0 ? q.x : px(rng), y = k % 7 == 0 ? q.y : py(rng);
    double d2 = reach2;
    for (size_t i = 1; i < op.points.size(); ++i) {
      const Vec2 &s = op.points[i - 1], &e = op.points[i];
      if (x < std::min(s.x, e.x) - a || x > std::max(s.x, e.x) + a || y < std::min(s.y, e.y) - a || y > std::max(s.y, e.y) + a)
        continue;
      d2 = std::min(d2, kernels::segmentDistance2(x, y, s.x, s.y, e.x, e.y));
    }
    const double u = d2 / reach2;
    const double want = u >= 1.0 ? 0.0 : op.strength * (1.0 - u * u) * (1.0 - u * u);
    const double got = prepared.patinaAt(x, y);
    ASSERT_EQ(std::memcmp(&got, &want, sizeof got), 0) << "at " << x << ", " << y << ": " << got << " for " << want;
    inside += got > 0.0;
  }
  EXPECT_GT(inside, 3000);
}

TEST(Patina, SettlesIntoTheHollows) {
  ShadingParams s;
  s.metal = *metalByName("copper");
  const glm::dvec3 p(0, 0, 0.5), n(0, 0, 1), view = glm::normalize(glm::dvec3(0, 0.3, -1));
  Patina black;
  black.amount[1] = 0.8;
  const double open = glm::dot(shadeMetal(s, p, n, view, 0.0), glm::dvec3(1));
  const double tinted = glm::dot(shadeMetal(s, p, n, view, 0.0, &black), glm::dvec3(1));
  const double tintedHollow = glm::dot(shadeMetal(s, p, n, view, 1.0, &black), glm::dvec3(1));
  const double bareHollow = glm::dot(shadeMetal(s, p, n, view, 1.0), glm::dvec3(1));
  EXPECT_LT(tinted, 0.6 * open);                          // the brush shows on open metal
  EXPECT_LT(tintedHollow / bareHollow, tinted / open);   // and more in a hollow
  Patina green;
  green.amount[3] = 0.8;
  const glm::dvec3 g = shadeMetal(s, p, n, view, 0.0, &green);
  const glm::dvec3 c = shadeMetal(s, p, n, view, 0.0);
  EXPECT_GT(g.g / g.r, c.g / c.r);  // verdigris turns copper toward green
}

TEST(Patina, UndoTakesItAwayExactly) {
  auto scene = parseScene(kScene, "patina.json", ".");
  ASSERT_TRUE(scene);
  Scene bare = *scene;
  bare.operations.pop_back();
  auto model = bare.makeModel();
  ASSERT_TRUE(model);
  ThreadPool pool(2);
  Renderer r(pool);
  r.setCamera(Camera(scene->camera, 160, 100));
  const ShadingParams s = copper(*model);
  r.setShading(s);
  r.sync(*model);
  Image before;
  ASSERT_TRUE(r.renderFull(before));
  ASSERT_TRUE(model->add(scene->operations[1]).ok());
  r.sync(*model);
  Image image = before;
  const PixelSpans dirty = r.dirtySpans(*model, 1);
  EXPECT_GT(dirty.area(), 0);
  EXPECT_LT(dirty.area(), 160 * 100);
  ASSERT_TRUE(r.render(image, dirty));
  int darker = 0;
  for (int y = 0; y < 100; ++y)
    for (int x = 0; x < 160; ++x) darker += image.pixel(x, y)[1] + 8 < before.pixel(x, y)[1];
  EXPECT_GT(darker, 500) << "the black stroke darkens the metal under it";

  ASSERT_TRUE(model->undo());
  r.sync(*model);
  ASSERT_TRUE(r.render(image, r.dirtySpans(*model, 1)));
  for (int y = 0; y < 100; ++y)
    for (int x = 0; x < 160; ++x)
      for (int k = 0; k < 4; ++k) ASSERT_EQ(image.pixel(x, y)[k], before.pixel(x, y)[k]) << x << "," << y;
}

// A sheet with a patina somewhere is shaded in lanes like one without, and only the hits under a
// stroke one at a time with it: beyond the brush's reach its pixels are the bytes of the sheet
// without the stroke.
TEST(Patina, BeyondTheStrokeTheMetalIsTheSameBytes) {
  auto scene = parseScene(kScene, "patina.json", ".");
  ASSERT_TRUE(scene);
  Scene bare = *scene;
  bare.operations.pop_back();
  auto with = scene->makeModel();
  auto without = bare.makeModel();
  ASSERT_TRUE(with && without);
  ThreadPool pool(2);
  const Camera camera(scene->camera, 160, 100);
  auto picture = [&](const Model& model) {
    Renderer r(pool);
    r.setCamera(camera);
    const ShadingParams s = copper(model);
    r.setShading(s);
    r.sync(model);
    Image image;
    EXPECT_TRUE(r.renderFull(image));
    return image;
  };
  const Image a = picture(*with), b = picture(*without);
  Renderer r(pool);
  r.setCamera(camera);
  r.sync(*with);
  int beyond = 0, under = 0, darker = 0;
  for (int y = 0; y < 100; ++y)
    for (int x = 0; x < 160; ++x) {
      // The pixel's own ray and its neighbours' (an edge's extra rays) all hit beyond the brush,
      // or the middle of the stroke.
      double lo = 1e9, hi = -1e9;
      bool all = true;
      for (const auto& [dx, dy] : {std::pair{0, 0}, {-1, 0}, {1, 0}, {0, -1}, {0, 1}}) {
        std::optional<glm::dvec3> hit;
        ASSERT_TRUE(r.pick(*with, camera, x + dx + 0.5, y + dy + 0.5, hit));
        if (!hit) {
          all = false;
          break;
        }
        lo = std::min(lo, std::abs(hit->y)), hi = std::max(hi, std::abs(hit->y));
      }
      if (!all) continue;
      if (lo > 4.5) {
        ++beyond;
        for (int k = 0; k < 4; ++k) ASSERT_EQ(a.pixel(x, y)[k], b.pixel(x, y)[k]) << x << "," << y;
      } else if (hi < 2.0) {
        ++under;
        darker += a.pixel(x, y)[1] + 8 < b.pixel(x, y)[1];
      }
    }
  EXPECT_GT(beyond, 1000);
  EXPECT_GT(under, 500);
  EXPECT_GT(darker, under * 3 / 4) << "the black stroke darkens the metal under it";
}

// The strokes of a wide brush are read from a lattice of nodes kept block by block: a stroke
// that comes, grows (the kiosk's stroke in the making, replaced at each pen event) or goes
// forgets the blocks under it, so a dirty update over a lattice read by the frames before gives
// the bytes of a full render of a renderer that never saw them.
TEST(Patina, AStrokeOverALatticeReadBeforeGivesTheBytesOfAFullRender) {
  auto scene = parseScene(kScene, "patina.json", ".");
  ASSERT_TRUE(scene);
  auto model = scene->makeModel();
  ASSERT_TRUE(model);
  ASSERT_TRUE(PatinaCache::kept(model->operations()[1].op()));
  ThreadPool pool(2);
  const Camera camera(scene->camera, 160, 100);
  const ShadingParams s = copper(*model);
  auto fresh = [&](const Model& m) {
    Renderer r(pool);
    r.setCamera(camera);
    r.setShading(s);
    r.sync(m);
    Image image;
    EXPECT_TRUE(r.renderFull(image));
    return image;
  };
  auto same = [](const Image& a, const Image& b, const char* what) {
    int differ = 0;
    for (int y = 0; y < a.height; ++y)
      for (int x = 0; x < a.width; ++x)
        for (int k = 0; k < 4; ++k) differ += a.pixel(x, y)[k] != b.pixel(x, y)[k];
    EXPECT_EQ(differ, 0) << what;
  };
  Renderer r(pool);
  r.setCamera(camera);
  r.setShading(s);
  r.sync(*model);
  Image image;
  ASSERT_TRUE(r.renderFull(image));  // (every block under the first stroke read)
  const Image first = image;
  // A green stroke across the black one, then the same stroke grown (the kiosk replaces its
  // stroke in the making at each pen event), then undone.
  Operation green;
  green.kind = OpKind::Patina;
  green.tinge = 3;
  green.a = 3.0;
  green.strength = 0.8;
  green.points = {{-2, -8}, {1, -1}};
  ASSERT_TRUE(model->add(green).ok());
  r.sync(*model);
  PixelSpans dirty = r.dirtySpans(*model, 2);
  EXPECT_LT(dirty.area(), 160 * 100);
  ASSERT_TRUE(r.render(image, dirty));
  same(image, fresh(*model), "a stroke added");
  const PixelSpans before = r.dirtySpans(*model, 2);
  ASSERT_TRUE(model->undo());
  green.points.push_back({3, 5});
  ASSERT_TRUE(model->add(green).ok());
  r.sync(*model);
  ASSERT_TRUE(r.render(image, before.united(r.dirtySpans(*model, 2))));
  same(image, fresh(*model), "the stroke grown");
  ASSERT_TRUE(model->undo());
  r.sync(*model);
  ASSERT_TRUE(r.render(image, r.dirtySpans(*model, 2)));
  same(image, first, "the stroke undone");
  same(image, fresh(*model), "the stroke undone, against a fresh renderer");
}

// The lattice's amounts are the strokes' within a few levels of a byte: the picture with it and
// with every stroke worked out at every hit (RenderOptions::patinaLattice false).
TEST(Patina, TheLatticeIsTheStrokesWithinAFewLevels) {
  auto scene = parseScene(kScene, "patina.json", ".");
  ASSERT_TRUE(scene);
  auto model = scene->makeModel();
  ASSERT_TRUE(model);
  ThreadPool pool(2);
  const Camera camera(scene->camera, 320, 200);
  auto picture = [&](bool lattice) {
    Renderer r(pool);
    RenderOptions o;
    o.patinaLattice = lattice;
    r.setOptions(o);
    r.setCamera(camera);
    const ShadingParams s = copper(*model);
    r.setShading(s);
    r.sync(*model);
    Image image;
    EXPECT_TRUE(r.renderFull(image));
    EXPECT_GT(r.memoryBytes(), 0u);
    return image;
  };
  const Image a = picture(true), b = picture(false);
  int worst = 0, differ = 0;
  for (int y = 0; y < a.height; ++y)
    for (int x = 0; x < a.width; ++x)
      for (int k = 0; k < 3; ++k) {
        const int d = std::abs(a.pixel(x, y)[k] - b.pixel(x, y)[k]);
        worst = std::max(worst, d), differ += d > 0;
      }
  EXPECT_LE(worst, 4);
  EXPECT_LT(differ, a.width * a.height * 3 / 20);
}

// The lattice itself: a block is worked out once, on the first read, and read bilinearly; the
// blocks under a region are forgotten and worked out again.
TEST(Patina, TheLatticeKeepsABlockUntilARegionOverItIsForgotten) {
  PatinaCache cache;
  EXPECT_FALSE(cache.configure(Box2{-10, -10, 10, 10}));
  EXPECT_TRUE(cache.configure(Box2{-10, -10, 10, 10}));
  int fills = 0;
  // A field linear in x and y, per tinge: bilinear interpolation gives it back.
  auto fill = [&](int i0, int j0, float* v) {
    ++fills;
    for (int j = 0; j < PatinaCache::kBlockNodes; ++j)
      for (int i = 0; i < PatinaCache::kBlockNodes; ++i)
        for (int t = 0; t < PatinaCache::kTinges; ++t)
          v[(j * PatinaCache::kBlockNodes + i) * PatinaCache::kTinges + t] =
              static_cast<float>(0.5 + 0.01 * (t + 1) * cache.nodeX(i0 + i) - 0.02 * cache.nodeY(j0 + j));
    return true;
  };
  double out[PatinaCache::kTinges];
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-9.9, 9.9);
  for (int k = 0; k < 200; ++k) {
    const double x = u(rng), y = u(rng);
    ASSERT_TRUE(cache.covers(x, y));
    cache.at(x, y, fill, out);
    for (int t = 0; t < PatinaCache::kTinges; ++t) EXPECT_NEAR(out[t], 0.5 + 0.01 * (t + 1) * x - 0.02 * y, 1e-6);
  }
  // 20 mm at 4 mm a block (16 cells of 0.25 mm): 5 x 5 blocks.
  EXPECT_EQ(fills, 25);
  EXPECT_EQ(cache.blocksWorkedOut(), 25u);
  EXPECT_EQ(cache.memoryBytes(), 25 * PatinaCache::kBlockFloats * sizeof(float));
  cache.at(0.0, 0.0, fill, out);
  EXPECT_EQ(fills, 25) << "a block is worked out once";
  // The region's block and those around it (a block's edge nodes are its neighbours' too).
  cache.invalidate(Box2{-1, -1, 1, 1});
  EXPECT_EQ(cache.blocksWorkedOut(), 25u - 9u);
  cache.at(0.0, 0.0, fill, out);
  EXPECT_EQ(fills, 26);
  EXPECT_FALSE(cache.covers(10.5, 0.0));
  cache.clear();
  EXPECT_EQ(cache.blocksWorkedOut(), 0u);
  // Blocks no stroke reaches: read as zeros, worked out once, holding no memory of their own.
  int empty = 0;
  auto none = [&](int, int, float*) {
    ++empty;
    return false;
  };
  for (double y = -9.5; y < 10.0; y += 1.0)
    for (double x = -9.5; x < 10.0; x += 1.0) {
      cache.at(x, y, none, out);
      for (int t = 0; t < PatinaCache::kTinges; ++t) EXPECT_EQ(out[t], 0.0);
    }
  EXPECT_EQ(empty, 25);
  EXPECT_EQ(cache.blocksWorkedOut(), 0u);
  EXPECT_EQ(cache.memoryBytes(), 0u);
  cache.invalidate(Box2{-1, -1, 1, 1});
  cache.at(0.0, 0.0, fill, out);
  EXPECT_EQ(fills, 27);
  EXPECT_EQ(cache.blocksWorkedOut(), 1u);
}

TEST(Patina, TheKioskBrushLaysOneStrokeWhenThePenLifts) {
  const ToolSpec* brush = nullptr;
  for (const auto& t : toolCatalogue())
    if (t.name == "Green patina") brush = &t;
  ASSERT_NE(brush, nullptr);
  StrokeBuilder b;
  b.begin(*brush, *metalByName("copper"));
  size_t handed = 0;
  for (int i = 0; i <= 40; ++i) handed += b.add(StrokePoint{-10 + 0.5 * i, 2.0, 0.5, 0.6}).size();
  EXPECT_EQ(handed, 0u) << "nothing is laid while the brush moves";
  const auto f = b.end();
  ASSERT_EQ(f.rest.size(), 1u);
  const Operation& op = f.rest[0];
  EXPECT_EQ(op.kind, OpKind::Patina);
  EXPECT_EQ(tinges()[static_cast<size_t>(op.tinge)].name, "green");
  EXPECT_DOUBLE_EQ(op.a, 0.5 * brush->size);
  EXPECT_NEAR(op.strength, 0.25 + 0.75 * 0.6, 1e-9);
  EXPECT_GE(op.points.size(), 20u);
  EXPECT_TRUE(validate(op).empty()) << validate(op);
}

TEST(Patina, PovExportLayersTheTinge) {
  auto scene = parseScene(kScene, "patina.json", ".");
  ASSERT_TRUE(scene);
  auto model = scene->makeModel();
  ASSERT_TRUE(model);
  PovExportOptions opt;
  opt.width = 80, opt.height = 50;
  auto pov = exportPov(*scene, *model, opt);
  ASSERT_TRUE(pov) << pov.error();
  EXPECT_NE(pov->find("Emboss_Brush("), std::string::npos);
  EXPECT_NE(pov->find("rgbf <1, 1, 1, 1>"), std::string::npos);
  if (std::system("command -v povray >/dev/null 2>&1") != 0) GTEST_SKIP() << "povray is not installed";
  const auto dir = test::scratchDir("pov-patina");
  std::ofstream(dir / "scene.pov") << *pov;
  const std::string cmd = "cd '" + dir.string() + "' && povray +Iscene.pov +W80 +H50 +FN +Opov.png -D -V >povray.log 2>&1";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << test::readText(dir / "povray.log");
  auto png = readPng(dir / "pov.png");
  ASSERT_TRUE(png) << png.error();
}

// POV-Ray evaluates the export's tinge of the brush at points on the sheet: the same as ours, more
// in the groove than on the open metal beside it.
TEST(Patina, PovExportSettlesIntoTheHollows) {
  std::string text = kScene;
  text.replace(text.find(R"("metal": "copper",)"), 18, R"("metal": "copper", "tinge": "brown",)");
  auto scene = parseScene(text, "patina.json", ".");
  ASSERT_TRUE(scene);
  auto model = scene->makeModel();
  ASSERT_TRUE(model);
  auto pov = exportPov(*scene, *model, {});
  ASSERT_TRUE(pov) << pov.error();
  if (std::system("command -v povray >/dev/null 2>&1") != 0) GTEST_SKIP() << "povray is not installed";
  std::vector<std::uint32_t> all(model->activeCount());
  for (std::uint32_t i = 0; i < all.size(); ++i) all[i] = i;
  const auto D = [&](double x, double y) { return model->displacement(x, y, 0.0, std::span<const std::uint32_t>(all)); };
  const Operation& brush = model->operations()[1].op();
  ASSERT_TRUE(brush.isPatina());
  const double front = model->workpiece().bounds().z1, depth = ShadingParams{}.tingeDepth;
  struct Probe {
    double x, y, z, ours, oursScene;
  };
  const Tinge brown = *tingeByName("brown");
  std::vector<Probe> probes;
  for (double y : {0.0, 0.4, 0.8, 1.2, 2.0, 3.0}) {
    const double x = 1.3, z = front + D(x, y);  // on the front face, moved by the sheet
    const double settle = std::max(std::clamp((front - z) / depth, 0.0, 1.0), cavityAt(x, y, D));
    probes.push_back({x, y, z, std::min(1.0, model->operations()[1].patinaAt(x, y) * (0.75 + 0.25 * settle)),
                      brown.strength * (0.25 + 0.75 * settle)});
  }
  const auto dir = test::scratchDir("pov-patina-settle");
  std::ofstream(dir / "scene.pov") << *pov;
  {
    std::ofstream probe(dir / "probe.pov");
    probe << std::setprecision(17) << "#declare Emboss_Declare_Only = 1;\n#include \"scene.pov\"\n#fopen Out \"values.txt\" write\n";
    for (const auto& p : probes)
      for (const char* f : {"Emboss_Tinge_black", "Emboss_Tinge_scene"})
        probe << "#write (Out, str(" << f << "(" << p.x << ", " << p.y << ", " << -p.z << "), 0, 16), \"\\n\")\n";
    probe << "#fclose Out\ncamera { location <0, 0, -10> look_at <0, 0, 0> }\n";
  }
  const std::string cmd = "cd '" + dir.string() + "' && povray +Iprobe.pov +W2 +H2 -GA +O/dev/null -D -V >povray.log 2>&1";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << test::readText(dir / "povray.log");
  std::ifstream values(dir / "values.txt");
  for (const auto& p : probes) {
    double theirs = -1, theirsScene = -1;
    ASSERT_TRUE(values >> theirs >> theirsScene) << test::readText(dir / "povray.log");
    EXPECT_NEAR(theirs, p.ours, 1e-9) << "the brush, at y = " << p.y << " (z " << p.z << ")";
    EXPECT_NEAR(theirsScene, p.oursScene, 1e-9) << "the scene's tinge, at y = " << p.y << " (z " << p.z << ")";
  }
  // The groove's floor holds more of the tinge than the open metal 3 mm away, beyond what the
  // brush's own fall-off gives.
  const double brushRatio = brush.strength > 0 ? model->operations()[1].patinaAt(1.3, 3.0) / model->operations()[1].patinaAt(1.3, 0.0) : 1.0;
  EXPECT_LT(probes.back().ours / probes.front().ours, brushRatio * 0.8);
  EXPECT_GT(probes.front().z, -1.0);  // sanity: the probes are on the sheet
}

}  // namespace
}  // namespace emboss
