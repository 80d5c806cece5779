// The rays set up in SIMD lanes (ray_lanes.h) are the bits Camera::rayAt() and clipRay() give one
// ray at a time, with the grid's ends and the reach Renderer::beginWalk() finds from them: over
// perspective and orthographic cameras, from above, at a slant and low down, for image points
// inside the image and beyond it, and for counts that fill no whole vector.
#include <gtest/gtest.h>
#include <hwy/targets.h>

#include <cstdint>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "render/camera.h"
#include "render/ray_lanes.h"
#include "render/renderer_internal.h"  // clipRay(), kSubdivisions: the scalar set-up
#include "util/portable_math.h"

namespace emboss {
namespace {

using render_internal::clipRay;
using render_internal::kSubdivisions;

bool sameBits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

CameraSpec perspective(Vec3 eye, Vec3 target) {
  CameraSpec c;
  c.eye = eye, c.target = target;
  return c;
}

// Checks every point's start against the scalar set-up; returns how many rays were clipped and
// how many were left to the caller.
void expectSameAsAlone(const Camera& camera, const Box3& clip, double h, const std::vector<double>& xs,
                       const std::vector<double>& ys, int& clipped, int& alone, const std::string& what) {
  RayStarts s;
  const double h8 = h / kSubdivisions;
  raysInLanes(camera.basis(), clip, h, h8, xs.data(), ys.data(), static_cast<int>(xs.size()), s);
  ASSERT_EQ(s.state.size(), xs.size());
  clipped = alone = 0;
  for (size_t i = 0; i < xs.size(); ++i) {
    const Ray ray = camera.rayAt(xs[i], ys[i]);
    const std::string at = what + " point (" + std::to_string(xs[i]) + ", " + std::to_string(ys[i]) + ")";
    const bool tiny = std::abs(ray.dir.x) < 1e-15 || std::abs(ray.dir.y) < 1e-15 || std::abs(ray.dir.z) < 1e-15;
    if (tiny) {
      EXPECT_EQ(s.state[i], RayStarts::kAlone) << at;
      ++alone;
      continue;
    }
    double t0, t1;
    const bool in = clipRay(ray, clip, t0, t1);
    ASSERT_EQ(s.state[i], in ? RayStarts::kClipped : RayStarts::kMisses) << at;
    for (int k = 0; k < 3; ++k) {
      const double got[2] = {k == 0 ? s.ox[i] : k == 1 ? s.oy[i] : s.oz[i], k == 0 ? s.dx[i] : k == 1 ? s.dy[i] : s.dz[i]};
      EXPECT_TRUE(sameBits(got[0], ray.origin[k])) << at << " origin " << k;
      EXPECT_TRUE(sameBits(got[1], ray.dir[k])) << at << " direction " << k;
    }
    if (!in) continue;
    ++clipped;
    const long q0 = kSubdivisions * floorToLong(t0 / h), q1 = kSubdivisions * ceilToLong(t1 / h);
    EXPECT_EQ(kSubdivisions * static_cast<long>(s.g0[i]), q0) << at;
    EXPECT_EQ(kSubdivisions * static_cast<long>(s.g1[i]), q1) << at;
    const glm::dvec3 pa = ray.origin + (static_cast<double>(q0) * h8) * ray.dir;
    const glm::dvec3 pb = ray.origin + (static_cast<double>(q1) * h8) * ray.dir;
    EXPECT_TRUE(sameBits(s.rx0[i], std::min(pa.x, pb.x))) << at;
    EXPECT_TRUE(sameBits(s.ry0[i], std::min(pa.y, pb.y))) << at;
    EXPECT_TRUE(sameBits(s.rx1[i], std::max(pa.x, pb.x))) << at;
    EXPECT_TRUE(sameBits(s.ry1[i], std::max(pa.y, pb.y))) << at;
  }
}

// Every view's points against the scalar set-up (the instruction set Highway chose).
void expectEveryViewSameAsAlone() {
  const Box3 clip{-100.5, -75.25, -3.0, 100.5, 75.25, 9.5};
  std::vector<CameraSpec> specs{
      perspective({0, -60, 160}, {0, 0, 0}),       // the default view
      perspective({0, 0, 200}, {0, 0, 0}),         // straight down
      perspective({30, -170, 95}, {5, 10, 0}),     // at a slant
      perspective({-220, 40, 12}, {0, 0, 0}),      // low down, beside the box
      perspective({10, -8, 6}, {10, -7.5, 0}),     // close up, over the box
  };
  CameraSpec ortho = perspective({20, -40, 150}, {0, 0, 0});
  ortho.type = CameraSpec::Type::Ortho, ortho.height = 180.0;
  specs.push_back(ortho);
  std::mt19937_64 rng(51);
  for (size_t c = 0; c < specs.size(); ++c) {
    const Camera camera(specs[c], 320, 200);
    // Pixel centres of whole rows (a row of the renderer), random points, points beyond the image
    // and the image's centre, in a count that fills no whole vector.
    std::vector<double> xs, ys;
    for (int y : {0, 77, 100, 199})
      for (int x = 0; x < 320; ++x) xs.push_back(x + 0.5), ys.push_back(y + 0.5);
    std::uniform_real_distribution<double> ux(-80.0, 400.0), uy(-50.0, 250.0);
    for (int k = 0; k < 997; ++k) xs.push_back(ux(rng)), ys.push_back(uy(rng));
    xs.push_back(160.0), ys.push_back(100.0);
    int clipped = 0, alone = 0;
    expectSameAsAlone(camera, clip, 0.25, xs, ys, clipped, alone, "camera " + std::to_string(c));
    EXPECT_GT(clipped, 100) << "camera " << c;   // (each view sees the box)
    EXPECT_LT(clipped, static_cast<int>(xs.size())) << "camera " << c;  // (and points that miss it)
    // One and three points: fewer than a vector.
    for (int n : {1, 3}) {
      const std::vector<double> sx(xs.begin() + 500, xs.begin() + 500 + n), sy(ys.begin() + 500, ys.begin() + 500 + n);
      int c1 = 0, a1 = 0;
      expectSameAsAlone(camera, clip, 0.125, sx, sy, c1, a1, "camera " + std::to_string(c) + ", n " + std::to_string(n));
    }
  }
}

TEST(RayLanes, TheSameBitsAsEachRaySetUpAlone) { expectEveryViewSameAsAlone(); }

TEST(RayLanes, TheSameBitsOnEveryInstructionSetOfThisMachine) {
  // Each instruction set this machine has and the build compiled for (AVX-512, AVX2, SSE4 and
  // SSSE3 on an x86 of today; NEON and SVE on arm64), chosen in turn: a board without the
  // widest one takes another's lanes.
  int sets = 0;
  for (const std::int64_t target : hwy::SupportedAndGeneratedTargets()) {
    if (target == HWY_SCALAR || target == HWY_EMU128) continue;  // (Highway's fallbacks, not SIMD)
    hwy::SetSupportedTargetsForTest(target);
    SCOPED_TRACE(hwy::TargetName(target));
    expectEveryViewSameAsAlone();
    ++sets;
  }
  hwy::SetSupportedTargetsForTest(0);
  EXPECT_GE(sets, 1);
}

TEST(RayLanes, ARayAlongAnAxisIsLeftToTheCaller) {
  // Straight down through the image's centre: the direction's x and y are zero, where clipRay()
  // takes the slab apart.
  CameraSpec spec = perspective({0, 0, 200}, {0, 0, 0});
  const Camera camera(spec, 320, 200);
  const std::vector<double> xs{160.0, 170.5, 150.5}, ys{100.0, 90.5, 110.5};
  int clipped = 0, alone = 0;
  expectSameAsAlone(camera, Box3{-50, -50, -2, 50, 50, 2}, 0.25, xs, ys, clipped, alone, "straight down");
  EXPECT_EQ(alone, 1);
  EXPECT_EQ(clipped, 2);
}

}  // namespace
}  // namespace emboss
