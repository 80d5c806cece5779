// The field tracer's walks taken in SIMD lanes (walk_lanes.h) find the hits each ray's walk finds
// alone: the same bytes, over plates and discs, from above, at a slant, low down and close up
// (where rays leave the field's domain), with set operations whose windows the lanes stop at.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <random>
#include <string>
#include <tuple>
#include <vector>

#include "app/view_orbit.h"
#include "frep/workpieces.h"
#include "bench/piece_generator.h"
#include "render/renderer.h"
#include "render/renderer_internal.h"  // clipUprightCapsule()
#include "render/walk_lanes.h"
#include "tools/metal.h"

namespace emboss {
namespace {

ShadingParams shading(const Model& m) {
  ShadingParams s;
  s.metal = *metalByName("copper");
  s.frontZ = m.workpiece().bounds().z1;
  return s;
}

// The number of pixels whose bytes differ, and the first of them.
std::string compare(const Image& a, const Image& b, int& differing) {
  differing = 0;
  std::string first;
  for (int y = 0; y < a.height; ++y)
    for (int x = 0; x < a.width; ++x)
      if (std::memcmp(a.pixel(x, y), b.pixel(x, y), 4) != 0 && differing++ == 0)
        first = "(" + std::to_string(x) + ", " + std::to_string(y) + ")";
  return first;
}


// The piece's own camera, and orbits round it: straight above, 30 and 60 degrees off it, low down,
// and close up.
std::vector<CameraSpec> viewsOf(const CameraSpec& base) {
  std::vector<CameraSpec> out{base};
  const Orbit o = orbitOf(base);
  for (const auto& [azimuth, elevation, distance] :
       {std::tuple{0.0, 90.0, 1.0}, {20.0, 60.0, 1.0}, {-35.0, 30.0, 1.0}, {60.0, 8.0, 1.0}, {10.0, 70.0, 0.25}}) {
    Orbit v = o;
    v.azimuthDeg = azimuth, v.elevationDeg = elevation, v.distance = o.distance * distance;
    out.push_back(cameraAt(v, base));
  }
  return out;
}

// A full frame of the model with these options.
Image frameWith(ThreadPool& pool, const Model& model, const Camera& camera, const RenderOptions& options,
                RenderStats& stats) {
  Renderer r(pool);
  r.setOptions(options);
  r.setCamera(camera);
  r.setShading(shading(model));
  r.sync(model);
  Image image;
  EXPECT_TRUE(r.renderFull(image, &stats));
  return image;
}

void expectSameWithAndWithoutLanes(const Model& model, const CameraSpec& base, const std::string& what) {
  ThreadPool pool(2);
  const std::vector<CameraSpec> views = viewsOf(base);
  std::uint64_t laneRays = 0, hits = 0;
  for (size_t k = 0; k < views.size(); ++k) {
    const Camera camera(views[k], 200, 130);
    Image images[2];
    RenderStats stats[2];
    for (int lanes = 0; lanes < 2; ++lanes) {
      RenderOptions o;
      o.walkLanes = lanes == 1;
      images[lanes] = frameWith(pool, model, camera, o, stats[lanes]);
    }
    int differing = 0;
    const std::string first = compare(images[0], images[1], differing);
    EXPECT_EQ(differing, 0) << what << ", view " << k << ": first at " << first;
    EXPECT_EQ(stats[0].laneRays, 0u);
    EXPECT_EQ(stats[0].hits, stats[1].hits) << what << ", view " << k;
    laneRays += stats[1].laneRays, hits += stats[1].hits;
  }
  // The lanes took most rays that hit (where SIMD has two lanes or more: every build here).
  if (walkLaneCount() >= 2) {
    EXPECT_GT(laneRays, hits / 2) << what;
  }
}

// A generated piece with `setOps` random set operations on top, with and without the lanes.
void expectPiece(const PieceOptions& opt, int operations, unsigned seed, int setOps, const std::string& what) {
  const GeneratedPiece piece = generatePiece(operations, seed, opt);
  auto model = piece.makeModel();
  ASSERT_TRUE(model.ok()) << model.error();
  PieceRandom rng(5);
  for (int k = 0; k < setOps; ++k) ASSERT_TRUE(model->add(randomSetOperation(rng, piece, opt.toolScale)).ok());
  expectSameWithAndWithoutLanes(*model, piece.camera, what);
}

TEST(WalkLanes, APlateGivesTheSameBytesAsEveryWalkAlone) {
  PieceOptions opt;
  opt.width = 120, opt.height = 80, opt.toolScale = 1.5;
  expectPiece(opt, 300, 41, 0, "plate");
}

TEST(WalkLanes, ADiscGivesTheSameBytesAsEveryWalkAlone) {
  PieceOptions opt;
  opt.shape = PieceShape::Disc, opt.width = opt.height = 90, opt.toolScale = 1.2;
  expectPiece(opt, 300, 42, 0, "disc");
}

// Set operations: a lane stops before a ray's (x, y) can enter one's support, and at its window.
TEST(WalkLanes, SetOperationsGiveTheSameBytesAsEveryWalkAlone) {
  PieceOptions opt;
  opt.width = 80, opt.height = 60, opt.toolScale = 2.0;
  expectPiece(opt, 120, 43, 4, "plate with set operations");
}

// The plate the balls' tests work on: 80 x 60 mm, its tools twice the generator's size.
PieceOptions ballsPlate() {
  PieceOptions opt;
  opt.width = 80, opt.height = 60, opt.toolScale = 2.0;
  return opt;
}

// A ball's window is the ray's stretch in the capsule where it can change f (the box's corners
// left out), and a lane walks to it over the ball's support: the same bytes as the box's windows,
// with offsets after the balls (their shift fields make the capsule tall), from every view; and
// the capsule does leave rays out.
TEST(WalkLanes, ABallsRoundWindowGivesTheBytesOfItsBox) {
  const PieceOptions opt = ballsPlate();
  const GeneratedPiece piece = generatePiece(120, 44, opt);
  auto model = piece.makeModel();
  ASSERT_TRUE(model.ok()) << model.error();
  PieceRandom rng(9);
  for (int k = 0; k < 5; ++k) ASSERT_TRUE(model->add(randomSetOperation(rng, piece, opt.toolScale)).ok());
  for (int k = 0; k < 12; ++k) ASSERT_TRUE(model->add(randomPunch(rng, piece, opt.toolScale)).ok());
  ThreadPool pool(2);
  std::uint64_t leftOut[2] = {0, 0}, dense = 0;
  for (const CameraSpec& view : viewsOf(piece.camera)) {
    const Camera camera(view, 200, 130);
    Image images[2];
    for (int round = 0; round < 2; ++round) {
      RenderOptions o;
      o.roundWindows = round == 1;
      RenderStats st;
      images[round] = frameWith(pool, *model, camera, o, st);
      leftOut[round] += st.setOpsLeftOut, dense += st.denseRays;
    }
    int differing = 0;
    const std::string first = compare(images[0], images[1], differing);
    EXPECT_EQ(differing, 0) << "first at " << first;
  }
  EXPECT_EQ(dense, 0u) << "(a dense ray's window is sampled: the comparison wants none)";
  EXPECT_GT(leftOut[1], leftOut[0] + 1000) << "the capsules leave out the rays through their boxes' corners";
}

// A ball's smooth union: away from its tool a ray walks its window as outside it, its steps
// shortened by the ball's far raise (SetOp::farRaise); the same bytes as the whole window searched
// by intervals, from every view, in full frames and as a dirty update traces (no pile tops):
// balls resting on the relief and floating above it, of several sizes and blends, with offsets
// after them (their shift fields move the tool); and the far windows are walked.
TEST(WalkLanes, ABallsFarWindowsGiveTheBytesOfItsWholeWindow) {
  const PieceOptions opt = ballsPlate();
  const GeneratedPiece piece = generatePiece(120, 45, opt);
  auto model = piece.makeModel();
  ASSERT_TRUE(model.ok()) << model.error();
  const double top = piece.workpiece->halfThickness();
  auto ball = [&](double x, double y, double z, double r, double a1, double a2, double a3) {
    Operation o;
    o.kind = OpKind::BlendUnion;
    o.tool.type = ToolShape::Type::Sphere;
    o.tool.center = {x, y, z}, o.tool.r = r;
    o.a1 = a1, o.a2 = a2, o.a3 = a3;
    ASSERT_TRUE(model->add(o).ok());
  };
  ball(-12.0, 6.0, top + 1.2, 2.0, 0.27, 1.0, 2.0);  // the kiosk's bead, resting on the sheet
  ball(10.0, -4.0, top + 6.0, 1.0, 0.5, 1.0, 1.0);   // floating above it
  ball(2.0, 14.0, top + 2.0, 3.0, 1.0, 2.0, 6.0);    // a big one, a strong blend
  PieceRandom rng(11);
  for (int k = 0; k < 12; ++k) ASSERT_TRUE(model->add(randomPunch(rng, piece, opt.toolScale)).ok());
  ThreadPool pool(2);
  std::uint64_t steps[2] = {0, 0};
  for (const CameraSpec& view : viewsOf(piece.camera)) {
    const Camera camera(view, 200, 130);
    for (const bool pileTops : {true, false}) {
      Image images[2];
      for (int far = 0; far < 2; ++far) {
        RenderOptions o;
        o.ballFarWindows = far == 1;
        o.pileTops = pileTops;
        RenderStats st;
        images[far] = frameWith(pool, *model, camera, o, st);
        steps[far] += st.farSteps;
      }
      int differing = 0;
      const std::string first = compare(images[0], images[1], differing);
      EXPECT_EQ(differing, 0) << "pile tops " << pileTops << ": first at " << first;
    }
  }
  EXPECT_GT(steps[1], steps[0] + 1000) << "rays step through the balls' far windows";
}

// The capsule's stretch of a ray against points along it: inside within the radius, outside
// beyond it (rays from every side, through, past and along the axis).
TEST(WalkLanes, AnUprightCapsulesStretchHoldsThePointsWithinItsRadius) {
  using render_internal::clipUprightCapsule;
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const double x = 2.0, y = -1.0, z0 = 0.5, z1 = 3.0, radius = 1.5;
  auto distance = [&](const glm::dvec3& p) {
    const double z = std::clamp(p.z, z0, z1);
    return std::sqrt((p.x - x) * (p.x - x) + (p.y - y) * (p.y - y) + (p.z - z) * (p.z - z));
  };
  int met = 0, missed = 0;
  for (int k = 0; k < 2000; ++k) {
    glm::dvec3 o(x + 6.0 * u(rng), y + 6.0 * u(rng), 1.75 + 6.0 * u(rng));
    // Toward a point near the capsule (within 2 of its middle along each axis).
    glm::dvec3 d = glm::dvec3(x + 2.0 * u(rng), y + 2.0 * u(rng), 1.75 + 2.0 * u(rng)) - o;
    if (k % 10 == 0) d = glm::dvec3(0.0, 0.0, -1.0), o.z = 8.0;  // vertical
    if (k % 10 == 1) d.z = 0.0;                                  // level
    if (glm::length(d) < 1e-3) continue;
    d = glm::normalize(d);
    const Ray ray{o, d};
    double t0 = 0.0, t1 = 0.0;
    const bool hit = clipUprightCapsule(ray, x, y, z0, z1, radius, t0, t1);
    met += hit, missed += !hit;
    for (int i = 0; i <= 400; ++i) {
      const double t = 0.05 * i;
      const double dist = distance(o + t * d);
      const bool in = hit && t >= t0 && t <= t1;
      if (in) {
        ASSERT_LE(dist, radius + 1e-9) << k << " at t " << t;
      } else {
        ASSERT_GE(dist, radius - 1e-9) << k << " at t " << t << (hit ? " (met)" : " (missed)");
      }
    }
  }
  EXPECT_GT(met, 200);
  EXPECT_GT(missed, 200);
}

// Under a patina the rays are still found in lanes (only the metal is shaded a hit at a time): a
// plate and a disc with patina strokes over their reliefs, one of them with set operations.
TEST(WalkLanes, APatinasPieceGivesTheSameBytesAsEveryWalkAlone) {
  for (const bool disc : {false, true}) {
    PieceOptions opt;
    if (disc) opt.shape = PieceShape::Disc, opt.width = opt.height = 90;
    else opt.width = 80, opt.height = 60;
    opt.toolScale = 1.5;
    const GeneratedPiece piece = generatePiece(150, disc ? 45 : 44, opt);
    auto model = piece.makeModel();
    ASSERT_TRUE(model.ok()) << model.error();
    PieceRandom rng(6);
    for (int k = 0; k < 6; ++k) {
      const Operation t = randomTraceSegment(rng, piece, 4.0);
      Operation op;
      op.kind = OpKind::Patina;
      op.points = t.points;
      op.tinge = 1 + k % 4;
      op.a = rng.uniform(3.0, 8.0);
      op.strength = rng.uniform(0.5, 1.0);
      ASSERT_TRUE(model->add(op).ok());
    }
    if (!disc) {
      for (int k = 0; k < 3; ++k) ASSERT_TRUE(model->add(randomSetOperation(rng, piece, opt.toolScale)).ok());
    }
    expectSameWithAndWithoutLanes(*model, piece.camera, disc ? "disc under a patina" : "plate under a patina");
  }
}

// An outline sheet (an imported vm medallion, W the slab or its column's bound where those decide
// it): lanes stop where the outline's program is wanted, and at a bead blended on beside it.
TEST(WalkLanes, AnOutlineSheetGivesTheSameBytesAsEveryWalkAlone) {
  auto outline = generateOutlinePiece(150, 5, 18.0, 0.5, 30, 5, true);
  ASSERT_TRUE(outline.ok()) << outline.error();
  const GeneratedPiece& piece = *outline;
  Model model(piece.workpiece, piece.deformation);
  for (const Operation& o : piece.operations) ASSERT_TRUE(model.add(o).ok());
  const Box3 b = piece.workpiece->bounds();
  Operation bead;
  bead.kind = OpKind::BlendUnion;
  bead.tool.type = ToolShape::Type::Sphere;
  bead.tool.r = 1.5;
  bead.tool.center = {b.x0 + 1.0, b.y0 + 1.0, 0.5};
  bead.a1 = 0.4, bead.a2 = 1.0, bead.a3 = 3.0;
  ASSERT_TRUE(model.add(bead).ok());
  expectSameWithAndWithoutLanes(model, piece.camera, "outline sheet");
}

// The normals in lanes against fieldNormal()'s formula over Grads, bit for bit: points on and
// beside each face, rim and edge of a plate and a disc, with D's slopes of either sign and zero
// (where two terms of the min tie, and where the normal has zero components), and an outline
// sheet's slab.
TEST(WalkLanes, NormalsInLanesAreTheGradsOwnBitForBit) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int kind : {1, 2, 4}) {
    const Plate plate(30.0, 20.0, 0.4);
    const Disc disc(25.0, 0.4);
    const Workpiece& w = kind == 1 ? static_cast<const Workpiece&>(plate) : disc;
    WalkSheet sheet;
    sheet.kind = kind, sheet.w = kind == 1 ? 30.0 : 25.0, sheet.h = 20.0, sheet.d = 0.4;
    constexpr int n = 4096;
    std::vector<double> x(n), y(n), z(n), dv(n), dgx(n), dgy(n), nx(n), ny(n), nz(n);
    for (int k = 0; k < n; ++k) {
      const int what = k % 8;
      x[k] = what == 1 ? 30.0 : what == 2 ? 0.0 : 26.0 * u(rng);
      y[k] = what == 3 ? -20.0 : what == 2 ? 0.0 : 18.0 * u(rng);
      dv[k] = what == 4 ? 0.0 : u(rng);
      dgx[k] = what == 5 ? 0.0 : 2.0 * u(rng);
      dgy[k] = what == 5 || what == 6 ? 0.0 : 2.0 * u(rng);
      z[k] = dv[k] + (what == 7 ? 0.4 : what == 6 ? 0.0 : 0.5 * u(rng));
    }
    const int done = sheetNormalLanes(sheet, x.data(), y.data(), z.data(), dv.data(), dgx.data(), dgy.data(), n,
                                      nx.data(), ny.data(), nz.data());
    if (walkLaneCount() >= 2) {
      EXPECT_GT(done, n - 16);
    }
    for (int k = 0; k < done; ++k) {
      const Grad d(dv[k], dgx[k], dgy[k], 0.0);
      const P3<Grad> q{Grad(x[k], 1, 0, 0), Grad(y[k], 0, 1, 0), Grad(z[k], 0, 0, 1)};
      // (An outline sheet's where W is its slab: fieldNormal()'s d - abs(z').)
      const Grad f = kind == 4 ? Grad(0.4) - abs(q.z - d) : w.value(P3<Grad>{q.x, q.y, q.z - d});
      glm::dvec3 m(-f.dx, -f.dy, -f.dz);
      const double len = glm::length(m);
      m = len > 0 ? m / len : glm::dvec3(0, 0, 1);
      ASSERT_EQ(std::memcmp(&m.x, &nx[k], 8), 0) << "kind " << kind << ", point " << k << ": " << m.x << " " << nx[k];
      ASSERT_EQ(std::memcmp(&m.y, &ny[k], 8), 0) << "kind " << kind << ", point " << k << ": " << m.y << " " << ny[k];
      ASSERT_EQ(std::memcmp(&m.z, &nz[k], 8), 0) << "kind " << kind << ", point " << k << ": " << m.z << " " << nz[k];
    }
  }
}

}  // namespace
}  // namespace emboss
