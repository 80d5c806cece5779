// The metal's optics: the conductor Fresnel term against the textbook complex-amplitude form, energy
// kept by the lobe, the cavity term, and the anti-aliasing of edges.
#include <complex>
#include <cmath>

#include <gtest/gtest.h>

#include "frep/model.h"
#include "render/renderer.h"
#include "render/shading.h"
#include "scene/scene.h"
#include "tools/metal.h"

namespace emboss {
namespace {

// The Fresnel amplitudes of s and p light for a complex index N = n + ik, from Snell's law with a
// complex refraction angle (Born and Wolf), averaged in power: an independent route to the same value.
double fresnelByAmplitudes(double cosI, double n, double k) {
  using C = std::complex<double>;
  const C N(n, k);
  const double sin2 = 1.0 - cosI * cosI;
  const C cosT = std::sqrt(C(1.0) - C(sin2) / (N * N));
  const C rs = (C(cosI) - N * cosT) / (C(cosI) + N * cosT);
  const C rp = (N * C(cosI) - cosT) / (N * C(cosI) + cosT);
  return 0.5 * (std::norm(rs) + std::norm(rp));
}

TEST(Shading, ConductorFresnelEqualsTheAmplitudeForm) {
  for (const Metal& m : metals())
    for (int c = 0; c < 3; ++c)
      for (double cosI : {1.0, 0.9, 0.7, 0.5, 0.3, 0.15, 0.05, 0.01}) {
        SCOPED_TRACE(std::string(m.name) + " channel " + std::to_string(c) + " cos " + std::to_string(cosI));
        EXPECT_NEAR(fresnelConductor(cosI, m.eta[c], m.k[c]), fresnelByAmplitudes(cosI, m.eta[c], m.k[c]), 1e-9);
      }
}

TEST(Shading, MetalsHaveTheirMeasuredColours) {
  const Metal copper = *metalByName("copper"), silver = *metalByName("silver"), brass = *metalByName("brass");
  // Normal incidence: copper reflects red far more than blue, silver is nearly neutral and bright,
  // brass is yellow (red and green above blue).
  EXPECT_NEAR(copper.f0[0], 0.924, 0.005);
  EXPECT_GT(copper.f0[0] - copper.f0[2], 0.3);
  EXPECT_GT(silver.f0[2], 0.85);
  EXPECT_LT(silver.f0[0] - silver.f0[2], 0.1);
  EXPECT_GT(brass.f0[1] - brass.f0[2], 0.1);
  // Grazing: every metal turns white.
  for (const Metal& m : metals())
    for (int c = 0; c < 3; ++c) EXPECT_GT(fresnelConductor(0.0, m.eta[c], m.k[c]), 0.999);
}

TEST(Shading, TheLobeKeepsTheEnergyOfAPerfectMirror) {
  // Fresnel 1 everywhere (k huge): single plus multiple scattering returns all the light, at every
  // roughness and angle (within the tables' sampling error); the single scattering alone loses
  // some at high roughness, which is why the compensation is there.
  for (double rough : {0.05, 0.2, 0.5, 0.9}) {
    Metal m = metals()[0];
    m.name = "test mirror";
    m.roughness = rough;
    m.eta = {1e-3, 1e-3, 1e-3};
    m.k = {1e4, 1e4, 1e4};
    for (double mu : {1.0, 0.7, 0.4, 0.15}) {
      SCOPED_TRACE("roughness " + std::to_string(rough) + " cos " + std::to_string(mu));
      const glm::dvec3 a = metalAlbedo(m, mu);
      EXPECT_NEAR(a.r, 1.0, 0.03);
    }
  }
  // A real metal returns less than a mirror, and copper's red more than its blue at every angle.
  const Metal copper = *metalByName("copper");
  for (double mu : {1.0, 0.5, 0.2}) {
    const glm::dvec3 a = metalAlbedo(copper, mu);
    EXPECT_LT(a.r, 1.0);
    EXPECT_GT(a.r, a.b);
  }
}

TEST(Shading, CavityIsFoundInGroovesAndNotOnOpenMetal) {
  // A flat sheet, a groove 0.4 mm deep and 1 mm wide along y, and a ridge.
  const auto groove = [](double x, double) { return -0.4 * std::exp(-x * x / 0.25); };
  const auto ridge = [](double x, double) { return 0.4 * std::exp(-x * x / 0.25); };
  const auto flat = [](double, double) { return 0.0; };
  EXPECT_EQ(cavityAt(0.0, 0.0, flat), 0.0);
  EXPECT_EQ(cavityAt(0.0, 0.0, ridge), 0.0);
  EXPECT_GT(cavityAt(0.0, 0.0, groove), 0.5);
  EXPECT_LT(cavityAt(3.0, 0.0, groove), 0.05);  // beyond the reach: open metal
  // Deeper is darker.
  const auto deep = [](double x, double) { return -0.8 * std::exp(-x * x / 0.25); };
  EXPECT_GT(cavityAt(0.0, 0.0, deep), cavityAt(0.0, 0.0, groove));
}

// A full frame of 320 x 200 of the piece through `camera`, in the scene's metal.
bool renderAt320x200(ThreadPool& pool, const Scene& scene, const Model& model, const CameraSpec& camera, Image& img,
                     RenderStats* st = nullptr) {
  Renderer r(pool);
  r.setCamera(Camera(camera, 320, 200));
  ShadingParams sp;
  sp.metal = *metalByName(scene.metal);
  sp.frontZ = model.workpiece().bounds().z1;
  r.setShading(sp);
  r.sync(model);
  return r.renderFull(img, st);
}

TEST(Shading, EdgesAreAntiAliasedAndOpenMetalIsNot) {
  auto scene = loadScene(std::string(EMBOSS_SOURCE_DIR) + "/firmware-app/pieces/2-shell.json");
  ASSERT_TRUE(scene) << scene.error();
  auto model = scene->makeModel();
  ASSERT_TRUE(model) << model.error();
  ThreadPool pool(2);
  Image img;
  RenderStats st;
  ASSERT_TRUE(renderAt320x200(pool, *scene, *model, scene->camera, img, &st));
  const long pixels = 320L * 200;
  // The sheet's outline and its grooves take extra rays; the rest of the frame does not.
  EXPECT_GT(st.edgePixels, 300u);
  EXPECT_LT(st.edgePixels, static_cast<std::uint64_t>(pixels / 10));
  EXPECT_EQ(st.rays, static_cast<std::uint64_t>(pixels + 2 * st.edgePixels));
  // Along the sheet's outline there are pixels between the backdrop and the metal.
  int blended = 0;
  for (int y = 0; y < 200; ++y)
    for (int x = 1; x < 320; ++x) {
      const std::uint8_t* a = img.pixel(x - 1, y);
      const std::uint8_t* b = img.pixel(x, y);
      if (std::abs(int(a[1]) - int(b[1])) > 0 && std::abs(int(a[1]) - int(b[1])) < 40) ++blended;
    }
  EXPECT_GT(blended, 100);
}

// The studio's ceiling is graduated from dim at the visitor's side to bright at the far side; a
// sheet seen straight down mirrors the ceiling straight up, which was its dim part: the shell read
// as dark brown from above and as bright copper from the kiosk's camera. Straight up is now a third
// as bright as the far side, and the face seen from above is not much darker than from the kiosk.
TEST(Shading, ASheetSeenStraightDownIsNotADarkMirror) {
  auto scene = loadScene(std::string(EMBOSS_SOURCE_DIR) + "/firmware-app/pieces/2-shell.json");
  ASSERT_TRUE(scene) << scene.error();
  auto model = scene->makeModel();
  ASSERT_TRUE(model) << model.error();
  ThreadPool pool(2);
  // The mean grey of the middle of the face (the sheet fills it from both cameras).
  auto faceGrey = [&](const CameraSpec& spec) {
    Image img;
    EXPECT_TRUE(renderAt320x200(pool, *scene, *model, spec, img));
    double sum = 0;
    int n = 0;
    for (int y = 60; y < 140; ++y)
      for (int x = 100; x < 220; ++x, ++n) {
        const std::uint8_t* p = img.pixel(x, y);
        sum += 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2];
      }
    return sum / n;
  };
  const CameraSpec kiosk = scene->camera;
  CameraSpec above = kiosk;
  const double distance = std::hypot(kiosk.eye.x - kiosk.target.x, kiosk.eye.y - kiosk.target.y, kiosk.eye.z - kiosk.target.z);
  above.eye = {kiosk.target.x, kiosk.target.y, kiosk.target.z + distance};
  const double fromKiosk = faceGrey(kiosk), fromAbove = faceGrey(above);
  std::printf("face's mean grey: %.1f from the kiosk's camera, %.1f from straight above\n", fromKiosk, fromAbove);
  EXPECT_GT(fromAbove, 0.7 * fromKiosk);
  EXPECT_LT(fromAbove, fromKiosk);  // the far side's strips are still the brightest
}

}  // namespace
}  // namespace emboss
