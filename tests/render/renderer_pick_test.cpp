// Renderer::pick: the point on the ray through a pixel as the renderer traces it, the model's
// surface within a few micrometres (pickSurface, on the model alone); declined when the renderer
// has not followed the model's last edit or looks through another camera.
#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include "app/surface_pick.h"
#include "bench/piece_generator.h"
#include "render/renderer.h"
#include "render/shading.h"

namespace emboss {
namespace {

TEST(RendererPick, FindsTheModelsSurfaceAndDeclinesWhenBehind) {
  PieceOptions opt;
  opt.width = 60, opt.height = 40, opt.halfThickness = 0.5;
  const GeneratedPiece piece = generatePiece(60, 31, opt);
  auto built = piece.makeModel();
  ASSERT_TRUE(built.ok()) << built.error();
  Model& model = *built;
  const Camera camera(piece.camera, 160, 100);
  ThreadPool pool(2);
  Renderer r(pool);
  r.setCamera(camera);
  r.setShading(sheetShading("copper", "none", model.workpiece().bounds().z1));
  r.sync(model);
  int both = 0, agree = 0;
  double worst = 0.0;
  for (int y = 0; y < camera.height(); y += 3)
    for (int x = 0; x < camera.width(); x += 3) {
      const double sx = x + 0.37, sy = y + 0.61;
      std::optional<glm::dvec3> hit;
      ASSERT_TRUE(r.pick(model, camera, sx, sy, hit));
      const auto want = pickSurface(model, camera, sx, sy);
      agree += hit.has_value() == want.has_value();
      if (hit && want) ++both, worst = std::max(worst, glm::length(*hit - *want));
    }
  const int n = ((camera.width() + 2) / 3) * ((camera.height() + 2) / 3);
  EXPECT_GT(both, n / 4) << "the sheet fills a good part of the picture";
  EXPECT_GE(agree, n - 3) << "a hit or a miss alike, but for a ray grazing the rim";
  EXPECT_LT(worst, 0.02) << "mm from the model's surface";

  // An edit the renderer has not followed yet: declined, until the next sync.
  PieceRandom rng(5);
  ASSERT_TRUE(model.add(randomPunch(rng, piece, 1.5)).ok());
  std::optional<glm::dvec3> hit;
  EXPECT_FALSE(r.pick(model, camera, 80, 50, hit));
  r.sync(model);
  EXPECT_TRUE(r.pick(model, camera, 80, 50, hit));
  // Another camera, or another model: declined.
  EXPECT_FALSE(r.pick(model, Camera(piece.camera, 320, 200), 80, 50, hit));
  const Model other(model.workpiecePtr(), model.deformation());
  EXPECT_FALSE(r.pick(other, camera, 80, 50, hit));
}

}  // namespace
}  // namespace emboss
