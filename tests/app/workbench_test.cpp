// The visitor's bench: picking, the tablet mapping, strokes, undo by strokes, turning the piece.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <optional>
#include <string>

#include "app/stroke_builder.h"
#include "app/surface_pick.h"
#include "app/workbench.h"
#include "frep/workpieces.h"
#include "scene/scene.h"
#include "tools/tool_catalogue.h"

namespace emboss {
namespace {

constexpr int kW = 640, kH = 400;

// An attract piece's model (firmware-app/pieces/<file>).
Result<Model> attractPieceModel(const std::string& file) {
  auto scene = loadScene(std::filesystem::path(EMBOSS_SOURCE_DIR) / "firmware-app" / "pieces" / file);
  if (!scene.ok()) return fail(scene.error());
  return scene->makeModel();
}

Workbench makeBench() {
  BenchSetup s;
  s.width = kW, s.height = kH;
  return Workbench(s);
}

// A visitor's fresh bench holding the catalogue's first tool of kind k.
Workbench benchWith(ToolKind k) {
  Workbench b = makeBench();
  b.resetForVisitor(0);
  while (b.tool().kind != k) b.apply(Action::NextTool, 0);
  return b;
}

// Screen position of a sheet point under the bench's current camera.
glm::dvec2 screenOf(const Workbench& b, double x, double y) {
  return *Camera(b.camera(), kW, kH).project({x, y, 0.5});
}

void drag(Workbench& b, const std::vector<Vec2>& mm, double pressure, double& t) {
  for (const auto& p : mm) {
    const auto s = screenOf(b, p.x, p.y);
    b.pen(s.x, s.y, pressure, true, true, t);
    t += 0.005;
  }
  const auto s = screenOf(b, mm.back().x, mm.back().y);
  b.pen(s.x, s.y, 0, false, true, t);
}

std::vector<Vec2> line(Vec2 a, Vec2 b, int n) {
  std::vector<Vec2> out;
  for (int i = 0; i <= n; ++i) out.push_back({a.x + (b.x - a.x) * i / n, a.y + (b.y - a.y) * i / n});
  return out;
}

TEST(SurfacePick, FindsTheFrontFaceAndMissesBesideTheSheet) {
  Model m(std::make_shared<Plate>(60.0, 40.0, 0.5), Deformation::Sheet);
  const CameraSpec spec = benchCamera(m.workpiece().bounds(), kW, kH);
  const Camera cam(spec, kW, kH);
  const auto c = cam.project({10, -5, 0.5});
  const auto hit = pickSurface(m, cam, c->x, c->y);
  ASSERT_TRUE(hit);
  EXPECT_NEAR(hit->x, 10, 0.05);
  EXPECT_NEAR(hit->y, -5, 0.05);
  EXPECT_NEAR(hit->z, 0.5, 0.01);
  EXPECT_FALSE(pickSurface(m, cam, 2, 2));  // the velvet in the corner
  // A raised boss lifts the picked point.
  Operation op;
  op.kind = OpKind::Punch;
  op.side = Side::Back;
  op.a = 5, op.p = 0.3, op.q = 1;
  op.at = {10, -5, 0.5};
  ASSERT_TRUE(m.add(op));
  const auto raised = pickSurface(m, cam, c->x, c->y);
  ASSERT_TRUE(raised);
  EXPECT_GT(raised->z, 1.5);
}

// Skipping the stretches of the march that intervals prove outside finds the very points that
// evaluating every sample finds: on an attract piece of 1366 operations, over the whole screen
// (the sheet, its raised and sunk relief, the velvet beside it).
TEST(SurfacePick, SkippingWhatIntervalsProveOutsideFindsTheSamePoints) {
  auto model = attractPieceModel("1-rosette.json");
  ASSERT_TRUE(model.ok()) << model.error();
  ASSERT_GT(model->activeCount(), 1000u);
  const Camera cam(benchCamera(model->workpiece().bounds(), kW, kH), kW, kH);
  int hits = 0, misses = 0;
  for (double y = 3.3; y < kH; y += 29)
    for (double x = 2.7; x < kW; x += 31) {
      const auto every = pickSurface(*model, cam, x, y, false), skipping = pickSurface(*model, cam, x, y);
      ASSERT_EQ(every.has_value(), skipping.has_value()) << x << ", " << y;
      if (!every) {
        ++misses;
        continue;
      }
      ++hits;
      EXPECT_EQ(every->x, skipping->x) << x << ", " << y;
      EXPECT_EQ(every->y, skipping->y) << x << ", " << y;
      EXPECT_EQ(every->z, skipping->z) << x << ", " << y;
    }
  EXPECT_GT(hits, 50);
  EXPECT_GT(misses, 20);
}

// Each of the pick's evaluations reads only the operations whose support holds its point or meets
// its box. The points are those of the same march over the whole model, every operation evaluated
// at every sample (written out here), on an attract piece at an angle: an oblique ray's footprint
// crosses many supports that its points do not.
TEST(SurfacePick, OperationsNearEachSampleFindTheWholeModelsPoints) {
  auto model = attractPieceModel("2-shell.json");
  ASSERT_TRUE(model.ok()) << model.error();
  const Camera cam(benchCamera(model->workpiece().bounds(), kW, kH), kW, kH);
  // The march of pickSurface(), every sample evaluated over every operation.
  auto whole = [&](double sx, double sy) -> std::optional<glm::dvec3> {
    const Ray ray = cam.rayAt(sx, sy);
    Box3 b = model->bounds();
    b.x0 -= 1, b.y0 -= 1, b.z0 -= 1, b.x1 += 1, b.y1 += 1, b.z1 += 1;
    double t0 = 0, t1 = std::numeric_limits<double>::infinity();
    const double o[3] = {ray.origin.x, ray.origin.y, ray.origin.z}, d[3] = {ray.dir.x, ray.dir.y, ray.dir.z};
    const double lo[3] = {b.x0, b.y0, b.z0}, hi[3] = {b.x1, b.y1, b.z1};
    for (int i = 0; i < 3; ++i) {
      if (std::abs(d[i]) < 1e-15) {
        if (o[i] < lo[i] || o[i] > hi[i]) return std::nullopt;
        continue;
      }
      double a = (lo[i] - o[i]) / d[i], c = (hi[i] - o[i]) / d[i];
      if (a > c) std::swap(a, c);
      t0 = std::max(t0, a), t1 = std::min(t1, c);
    }
    if (t0 > t1) return std::nullopt;
    auto f = [&](double t) {
      const glm::dvec3 p = ray.origin + ray.dir * t;
      return model->evaluate(P3<double>{p.x, p.y, p.z});
    };
    if (f(t0) >= 0) return ray.origin + ray.dir * t0;
    const double h = std::clamp(0.35 * model->workpiece().halfThickness(), 0.02, 0.25);
    double prev = t0;
    for (double t = t0 + h;; t += h) {
      const double s = std::min(t, t1);
      if (f(s) >= 0) {
        double a = prev, c = s;
        for (int i = 0; i < 40; ++i) {
          const double mid = 0.5 * (a + c);
          if (f(mid) >= 0) c = mid; else a = mid;
        }
        return ray.origin + ray.dir * c;
      }
      if (s >= t1) return std::nullopt;
      prev = s;
    }
  };
  int hits = 0, misses = 0;
  for (double y = 5.3; y < kH; y += 41)
    for (double x = 4.7; x < kW; x += 43) {
      const auto want = whole(x, y);
      for (const bool skipOutside : {false, true}) {
        const auto got = pickSurface(*model, cam, x, y, skipOutside);
        ASSERT_EQ(want.has_value(), got.has_value()) << x << ", " << y << (skipOutside ? ", skipping" : "");
        if (!want) continue;
        EXPECT_EQ(want->x, got->x) << x << ", " << y << (skipOutside ? ", skipping" : "");
        EXPECT_EQ(want->y, got->y) << x << ", " << y << (skipOutside ? ", skipping" : "");
        EXPECT_EQ(want->z, got->z) << x << ", " << y << (skipOutside ? ", skipping" : "");
      }
      ++(want ? hits : misses);
    }
  EXPECT_GT(hits, 30);
  EXPECT_GT(misses, 10);
}

TEST(SurfacePick, TabletAreaKeepsTheAspectAndCoversTheSheet) {
  const ScreenBox sheet{100, 50, 300, 200};
  const ScreenBox a = tabletArea(sheet, 1.6);
  EXPECT_NEAR(a.w / a.h, 1.6, 1e-9);
  EXPECT_LE(a.x, sheet.x);
  EXPECT_LE(a.y, sheet.y);
  EXPECT_GE(a.x + a.w, sheet.x + sheet.w);
  EXPECT_GE(a.y + a.h, sheet.y + sheet.h);
  EXPECT_NEAR(a.x + a.w / 2, 250, 1e-9);  // centred
}

TEST(Workbench, HomeViewLeavesRoomForThePanels) {
  const Workbench b = makeBench();
  const ScreenBox s = sheetOnScreen(Camera(b.camera(), kW, kH), b.model().workpiece().bounds());
  EXPECT_GE(s.x, benchSideRoom(kH) - 1);
  EXPECT_LE(s.x + s.w, kW - benchSideRoom(kH) + 1);
  EXPECT_GT(s.h, 0.6 * kH);
}

TEST(Workbench, AStrokeBecomesTheCatalogueOperationsOfThatStroke) {
  Workbench b = makeBench();
  b.resetForVisitor(0);
  double t = 0;
  const auto path = line({-20, 0}, {20, 8}, 80);
  drag(b, path, 0.6, t);
  EXPECT_EQ(b.strokes(), 1u);
  // The same stroke followed here: picked on the metal as it is at each sample (the stroke's own
  // early operations included, as the visitor sees them), through the catalogue.
  const Camera cam(b.camera(), kW, kH);
  Model replica(b.model().workpiecePtr(), Deformation::Sheet);
  StrokeBuilder sb;
  sb.begin(b.tool(), b.metal());
  std::vector<Operation> ops;
  for (const auto& p : path) {
    const auto s = screenOf(b, p.x, p.y);
    const auto hit = pickSurface(replica, cam, s.x, s.y);
    ASSERT_TRUE(hit);
    for (auto& op : sb.add({hit->x, hit->y, hit->z, 0.6})) {
      ASSERT_TRUE(replica.add(op));
      ops.push_back(op);
    }
  }
  const std::vector<StrokePoint> used = sb.points();
  const auto f = sb.end();
  ops.insert(ops.end(), f.rest.begin(), f.rest.end());
  const auto whole = strokeToOperations(b.tool(), b.metal(), used);
  ASSERT_EQ(whole.size(), ops.size());
  for (size_t i = 0; i < ops.size(); ++i) EXPECT_TRUE(sameOperation(whole[i], ops[i]));
  ASSERT_EQ(b.model().activeCount(), ops.size());
  EXPECT_GT(ops.size(), 5u);
  for (size_t i = 0; i < ops.size(); ++i) EXPECT_TRUE(sameOperation(b.model().operations()[i].op(), ops[i]));
  const auto ch = b.takeChanges();
  EXPECT_EQ(ch.ops.size(), ops.size());
}

// Going over the same place again and again with the blending punch stacks at most
// kMaxBlendsOnASpot beads there (more would make the tracer search the spot point by point); a
// first pass elsewhere is whole.
TEST(Workbench, TheBlendingPunchStacksAFewBeadsOnASpotAtMost) {
  Workbench b = benchWith(ToolKind::BlendPunch);
  double t = 0;
  const auto path = line({-20, 0}, {20, 0}, 80);
  drag(b, path, 0.6, t);
  const size_t firstPass = b.model().activeCount();
  ASSERT_GT(firstPass, 8u);
  for (int pass = 1; pass < 10; ++pass) drag(b, path, 0.6, t);
  const size_t onTheLine = b.model().activeCount();
  EXPECT_GE(onTheLine, 2 * firstPass);
  EXPECT_LE(onTheLine, static_cast<size_t>(Workbench::kMaxBlendsOnASpot + 1) * firstPass);
  // Each bead was admitted where fewer than kMaxBlendsOnASpot earlier ones covered its centre.
  const auto& ops = b.model().operations();
  for (size_t i = 0; i < onTheLine; ++i) {
    const Vec3& c = ops[i].op().tool.center;
    int covering = 0;
    for (size_t j = 0; j < i; ++j) {
      const Box3 box = ops[j].op().tool.bounds();
      covering += c.x >= box.x0 && c.x <= box.x1 && c.y >= box.y0 && c.y <= box.y1;
    }
    EXPECT_LT(covering, Workbench::kMaxBlendsOnASpot) << "bead " << i;
  }
  // A fresh line beside it takes every bead of its pass, and one undo takes them back.
  drag(b, line({-20, 12}, {20, 12}, 80), 0.6, t);
  EXPECT_NEAR(static_cast<double>(b.model().activeCount() - onTheLine), static_cast<double>(firstPass), 1.0);
  b.apply(Action::Undo, t);
  EXPECT_EQ(b.model().activeCount(), onTheLine);
}

// The metal's thickness along z at (x, y): the longest run of f >= 0 from `top` down to `bottom`
// (by default 3 mm above and below the plate), in steps of `step` (0 where a hole goes through);
// the search ends once a run reaches `enough`.
double thicknessAt(const Model& m, double x, double y, double top = 3.0, double bottom = -3.0, double step = 0.005,
                   double enough = std::numeric_limits<double>::infinity()) {
  double best = 0, run = 0;
  for (double z = top; z > bottom && best < enough; z -= step) {
    run = m.evaluate(P3<double>{x, y, z}) >= 0.0 ? run + step : 0.0;
    best = std::max(best, run);
  }
  return best;
}

// The height of the front face at (x, y): the first z from `top` down where f >= 0 (in steps of `step`).
double frontAt(const Model& m, double x, double y, double top = 3.0, double step = 0.002) {
  double z = top;
  while (z > -top && m.evaluate(P3<double>{x, y, z}) < 0.0) z -= step;
  return z;
}

// The flat punch's strikes in the model: regions lowered from the front.
std::vector<Operation> strikesOf(const Model& m) {
  std::vector<Operation> out;
  for (size_t i = 0; i < m.activeCount(); ++i) {
    const Operation& o = m.operations()[i].op();
    if (o.kind == OpKind::Region && o.side == Side::Front) out.push_back(o);
  }
  return out;
}

Vec2 centreOf(const Operation& strike) {
  Vec2 c;
  for (const auto& p : strike.points) c.x += 0.25 * p.x, c.y += 0.25 * p.y;
  return c;
}

// The depth a line of the flat punch's strikes beats the background down to: half the penetration
// depth at that pressure.
double bandDepth(const Workbench& b, double pressure) { return 0.5 * penetrationDepth(b.tool(), b.metal(), pressure); }

// A flat punch walked along a line beats a band of the background down evenly, to half the
// penetration depth: along the line, away from its ends, the sheet lies within 5 % of that below
// the plate (strikes apart by a margin leave ridges between them, and strikes meeting edge to edge
// left a groove and a ridge at every joint, 1.0 to 1.2 times the depth), and across the band too,
// out to 0.4 of the tool's size. Straight along x and on a diagonal, its faces turned along the
// stroke.
TEST(Workbench, TheFlatPunchBeatsABandDownEvenly) {
  for (const auto& [from, to] : {std::pair{Vec2{-20, 0}, Vec2{20, 0}}, std::pair{Vec2{-16, -11}, Vec2{16, 11}}}) {
    Workbench b = benchWith(ToolKind::FlatPunch);
    double t = 0;
    drag(b, line(from, to, 100), 1.0, t);
    const auto strikes = strikesOf(b.model());
    ASSERT_GE(strikes.size(), 20u);
    ASSERT_EQ(strikes.size(), b.model().activeCount());
    const double h = bandDepth(b, 1.0), top = b.model().workpiece().bounds().z1;
    ASSERT_GT(h, 0.3);
    // Away from the ends by a face and its descent: where every strike that reaches a point is there.
    const size_t margin = 7;
    const Vec2 a = centreOf(strikes[margin]), e = centreOf(strikes[strikes.size() - 1 - margin]);
    double lo = 1e9, hi = -1e9;
    for (int i = 0; i <= 200; ++i) {
      const double u = i / 200.0;
      const double depth = top - frontAt(b.model(), a.x + u * (e.x - a.x), a.y + u * (e.y - a.y));
      lo = std::min(lo, depth), hi = std::max(hi, depth);
    }
    EXPECT_GE(lo, 0.95 * h) << "from " << from.x << ", " << from.y;
    EXPECT_LE(hi, 1.05 * h) << "from " << from.x << ", " << from.y;
    const Vec2 c = centreOf(strikes[strikes.size() / 2]);
    const double len = std::hypot(to.x - from.x, to.y - from.y);
    const double nx = -(to.y - from.y) / len, ny = (to.x - from.x) / len;
    const double reach = 0.4 * b.tool().size;
    for (double v : {-reach, -0.5 * reach, 0.5 * reach, reach}) {
      const double depth = top - frontAt(b.model(), c.x + v * nx, c.y + v * ny);
      EXPECT_GE(depth, 0.95 * h) << v << " mm across";
      EXPECT_LE(depth, 1.05 * h) << v << " mm across";
    }
  }
}

// A single strike, a tap, goes the whole depth.
TEST(Workbench, TheFlatPunchsTapGoesTheWholeDepth) {
  Workbench b = benchWith(ToolKind::FlatPunch);
  double t = 0;
  drag(b, {{5, 5}}, 0.7, t);
  const auto strikes = strikesOf(b.model());
  ASSERT_EQ(strikes.size(), 1u);
  const Vec2 c = centreOf(strikes[0]);
  EXPECT_NEAR(b.model().workpiece().bounds().z1 - frontAt(b.model(), c.x, c.y), bandDepth(b, 0.7), 0.005);
}

// A flat punch beats the background down and never cuts through the sheet: struck hard five times
// along the same line of the 0.5 mm plate (the band 0.66 mm deep), the metal under the line keeps
// its thickness, it is beaten down by the first pass, and a spot sinks about three passes deep at
// most: a strike whose centre kMaxStrikesOnASpot earlier faces cover is left out.
TEST(Workbench, TheFlatPunchNeverCutsThroughTheSheet) {
  Workbench b = benchWith(ToolKind::FlatPunch);
  double t = 0;
  const auto path = line({-12, 0}, {12, 3}, 60);
  drag(b, path, 1.0, t);
  const size_t firstPass = b.model().activeCount();
  ASSERT_GT(firstPass, 10u);
  const double sheet = 2.0 * b.model().workpiece().halfThickness();
  const double top = b.model().workpiece().bounds().z1;
  // The first pass went down by more than a fifth of the sheet, at the line's middle.
  const double once = top - frontAt(b.model(), 0.0, 1.5);
  EXPECT_GT(once, 0.2 * sheet);
  for (int pass = 1; pass < 5; ++pass) drag(b, path, 1.0, t);
  EXPECT_GE(b.model().activeCount(), 2 * firstPass);
  EXPECT_LE(b.model().activeCount(), 3 * firstPass + 4);
  const double deepest = top - frontAt(b.model(), 0.0, 1.5);
  EXPECT_GT(deepest, 1.9 * once);
  EXPECT_LT(deepest, 3.2 * once);
  double thinnest = 1e9;
  for (int i = 0; i <= 48; ++i)
    for (double across : {-2.0, -1.0, 0.0, 1.0, 2.0}) {
      const double x = -12.0 + 0.5 * i, y = 1.5 * (x + 12.0) / 12.0 + across;
      thinnest = std::min(thinnest, thicknessAt(b.model(), x, y, 6.0, -6.0));
    }
  EXPECT_GE(thinnest, 0.95 * sheet) << "the flat punch thinned the sheet to " << thinnest << " mm";
  // Each strike was admitted where fewer than kMaxStrikesOnASpot earlier ones covered its centre.
  const auto strikes = strikesOf(b.model());
  for (size_t i = 0; i < strikes.size(); ++i) {
    const Vec2 c = centreOf(strikes[i]);
    int covering = 0;
    for (size_t j = 0; j < i; ++j) {
      const auto& q = strikes[j].points;
      bool in = false;
      for (size_t k = 0, l = q.size() - 1; k < q.size(); l = k++) {
        if ((q[k].y > c.y) == (q[l].y > c.y)) continue;  // the edge does not cross the strike's row
        if (c.x < q[k].x + (c.y - q[k].y) * (q[l].x - q[k].x) / (q[l].y - q[k].y)) in = !in;
      }
      covering += in;
    }
    EXPECT_LT(covering, Workbench::kMaxStrikesOnASpot) << "strike " << i;
  }
}

// Nor on a steep slope: round the flanks of a mound 9 mm high (six raised regions stacked), the
// strikes beat the metal under them down (under every strike's centre by its own depth at least,
// under most by 0.8 of the band's), the sheet bending as a whole and keeping its thickness,
// sampled each millimetre over every third strike's face (a flat box subtracted there cut
// terraces into the flank, and holes where it went deeper than the sheet).
TEST(Workbench, TheFlatPunchBeatsASteepSlopeDownWithoutCuttingIt) {
  Workbench b = benchWith(ToolKind::FlatPunch);
  std::string ops;
  for (int i = 0; i < 6; ++i)
    ops += std::string(i ? "," : "") +
           R"({"op": "region", "side": "back", "contour": [[-8, -8], [8, -8], [8, 8], [-8, 8]], "height": 1.5, "falloff": 1.5})";
  const auto scene = parseScene(R"({"format": "emboss-scene", "version": 1, "workpiece": {"type": "plate", "w": 120, "h": 80, "d": 0.5},
                                    "operations": [)" + ops + "]}",
                                "mound", ".");
  ASSERT_TRUE(scene.ok()) << scene.error();
  ASSERT_TRUE(b.restore(scene->operations, 6, {6}, {}, "copper", 1));
  double t = 0;
  for (double y : {-9.5, 9.5}) drag(b, line({-12, y}, {12, y}, 48), 1.0, t);
  for (double x : {-9.5, 9.5}) drag(b, line({x, -12}, {x, 12}, 48), 1.0, t);
  const Model& m = b.model();
  const auto mound = scene->makeModel();
  ASSERT_TRUE(mound.ok());
  const double sheet = 2.0 * m.workpiece().halfThickness(), h = bandDepth(b, 1.0);
  const auto strikes = strikesOf(m);
  EXPECT_GT(strikes.size(), 40u);
  double thinnest = 1e9;
  size_t shallow = 0, deep = 0;
  for (size_t i = 0; i < strikes.size(); ++i) {
    const Operation& s = strikes[i];
    const Vec2 c = centreOf(s);
    const double sunk = frontAt(*mound, c.x, c.y, 12.0) - frontAt(m, c.x, c.y, 12.0);
    shallow += sunk < s.height - 0.01;
    deep += sunk >= 0.8 * h;
    if (i % 3) continue;
    for (double u = -2.0; u <= 2.0; u += 1.0)
      for (double v = -2.0; v <= 2.0; v += 1.0)
        thinnest = std::min(thinnest, thicknessAt(m, c.x + u, c.y + v, 12.0, -4.0, 0.01, sheet));
  }
  EXPECT_EQ(shallow, 0u) << "strikes that did not beat the metal under them down by their own depth";
  EXPECT_GT(deep, strikes.size() / 2) << "strikes whose band was not beaten down";
  EXPECT_GE(thinnest, 0.95 * sheet) << "a strike on the slope thinned the sheet to " << thinnest << " mm";
}

TEST(Workbench, UndoAndRedoTakeWholeStrokes) {
  Workbench b = makeBench();
  double t = 0;
  drag(b, line({-20, 0}, {20, 0}, 60), 0.6, t);
  const size_t first = b.model().activeCount();
  b.apply(Action::NextTool, t);
  b.apply(Action::NextTool, t);
  b.apply(Action::NextTool, t);  // a punch
  drag(b, line({-20, 10}, {20, 10}, 60), 0.6, t);
  const size_t both = b.model().activeCount();
  ASSERT_GT(both, first);
  b.apply(Action::Undo, t);
  EXPECT_EQ(b.model().activeCount(), first);
  b.apply(Action::Undo, t);
  EXPECT_EQ(b.model().activeCount(), 0u);
  b.apply(Action::Undo, t);  // nothing left: harmless
  b.apply(Action::Redo, t);
  EXPECT_EQ(b.model().activeCount(), first);
  b.apply(Action::Redo, t);
  EXPECT_EQ(b.model().activeCount(), both);
  b.apply(Action::Undo, t);
  drag(b, line({-10, -10}, {10, -10}, 30), 0.6, t);  // a new stroke drops the redo tail
  b.apply(Action::Redo, t);
  EXPECT_LT(b.model().activeCount(), both + 1000);
  EXPECT_EQ(b.strokes(), 2u);
}

TEST(Workbench, ToolsSizesMetalsAndANewSheet) {
  Workbench b = makeBench();
  b.resetForVisitor(0);
  EXPECT_EQ(b.tool().name, "Tracer");
  const double size = b.tool().size;
  b.apply(Action::SizeUp, 0);
  EXPECT_NEAR(b.tool().size, size * 1.25, 1e-12);
  for (int i = 0; i < 10; ++i) b.apply(Action::SizeUp, 0);
  EXPECT_EQ(b.sizeStep(), kMaxSizeStep);
  b.apply(Action::PrevTool, 0);
  b.apply(Action::PrevTool, 0);
  EXPECT_EQ(b.toolIndex(), toolCatalogue().size() - 1);  // wraps round
  b.takeChanges();
  b.apply(Action::NextMetal, 0);
  EXPECT_EQ(std::string(b.metal().name), "brass");
  EXPECT_TRUE(b.takeChanges().full);
  double t = 0;
  drag(b, line({0, 0}, {10, 0}, 20), 0.5, t);
  b.apply(Action::NewSheet, t);
  EXPECT_EQ(b.model().activeCount(), 0u);
  EXPECT_EQ(std::string(b.metal().name), "brass");  // a new sheet keeps the visitor's choices
  b.resetForVisitor(t);
  EXPECT_EQ(std::string(b.metal().name), "copper");
}

TEST(Workbench, TurningOrbitsTheCameraAndComesBack) {
  Workbench b = makeBench();
  const CameraSpec home = b.camera();
  b.apply(Action::Turn, 10.0);
  EXPECT_TRUE(b.moving());
  b.update(10.45);
  EXPECT_TRUE(b.moving());
  EXPECT_TRUE(b.takeChanges().camera);
  b.update(11.0);
  EXPECT_FALSE(b.moving());
  EXPECT_TRUE(b.turned());
  const Orbit o = orbitOf(b.camera()), h = orbitOf(home);
  EXPECT_NEAR(o.azimuthDeg - h.azimuthDeg, -25, 1e-6);
  EXPECT_NEAR(o.elevationDeg, 50, 1e-6);
  EXPECT_NEAR(o.distance, h.distance * 1.1, 1e-6);
  // Embossing works on the turned piece: the pen's ray finds the metal.
  double t = 11;
  drag(b, line({-5, 0}, {5, 0}, 20), 0.6, t);
  EXPECT_GT(b.model().activeCount(), 0u);
  b.apply(Action::Turn, 12.0);
  b.update(13.0);
  EXPECT_FALSE(b.turned());
  EXPECT_EQ(b.camera().eye.x, home.eye.x);
  EXPECT_EQ(b.camera().eye.z, home.eye.z);
}

TEST(Workbench, HoverShowsTheFootprintAndLeavingTheMetalEndsTheStroke) {
  Workbench b = makeBench();
  const auto s = screenOf(b, 0, 0);
  b.pen(s.x, s.y, 0, false, true, 0);
  EXPECT_TRUE(b.hover().visible);
  EXPECT_FALSE(b.hover().touching);
  EXPECT_NEAR(b.hover().sx, s.x, 0.5);
  EXPECT_GT(b.hover().radius, 2.0);
  b.pen(s.x, s.y, 0.5, true, true, 0.01);
  EXPECT_TRUE(b.strokeActive());
  b.pen(1, 1, 0.5, true, true, 0.02);  // off the sheet
  EXPECT_FALSE(b.strokeActive());
  EXPECT_FALSE(b.hover().visible);
  b.penAway();
  EXPECT_EQ(b.pressure(), 0.0);
}

}  // namespace
}  // namespace emboss
