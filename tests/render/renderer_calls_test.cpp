// Two of the renderer's calls for the kiosk: a render with a deadline stops there, as a cancelled
// one does, and the rays it traced before keep their hits (the render after it gives the bytes of
// a render never stopped); pick() finds the point on the ray through a pixel as the renderer
// traces it, the model's surface within a few micrometres (pickSurface, on the model alone), and
// declines when the renderer has not followed the model's last edit or looks through another
// camera; without anti-aliasing a render traces one ray a pixel.
#include <gtest/gtest.h>

#include <chrono>
#include <cstring>

#include <glm/geometric.hpp>

#include "app/surface_pick.h"
#include "bench/piece_generator.h"
#include "render/renderer.h"
#include "render/shading.h"

namespace emboss {
namespace {

// A 60 x 40 mm plate 1 mm thick with a generated relief.
GeneratedPiece smallPiece(int operations, unsigned seed) {
  PieceOptions opt;
  opt.width = 60, opt.height = 40, opt.halfThickness = 0.5;
  return generatePiece(operations, seed, opt);
}

// r looking at the model through the camera, copper, in step with the model.
void lookAt(Renderer& r, const Model& model, const Camera& camera) {
  r.setCamera(camera);
  r.setShading(sheetShading("copper", "none", model.workpiece().bounds().z1));
  r.sync(model);
}

TEST(RenderDeadline, AStoppedRenderIsFinishedByTheNextToTheSameBytes) {
  const GeneratedPiece piece = smallPiece(40, 23);
  auto built = piece.makeModel();
  ASSERT_TRUE(built.ok()) << built.error();
  const Model& model = *built;
  const Camera camera(piece.camera, 240, 160);
  ThreadPool pool(2);

  Renderer reference(pool);
  lookAt(reference, model, camera);
  Image expected;
  ASSERT_TRUE(reference.renderFull(expected));

  Renderer r(pool);
  RenderOptions o;
  o.reuseHits = true;
  r.setOptions(o);
  lookAt(r, model, camera);
  Image image(camera.width(), camera.height());
  const Image blank = image;
  const PixelSpans all = PixelSpans::of(Rect{0, 0, camera.width(), camera.height()});
  // A deadline already past: nothing is traced, and the image is as it was.
  r.setDeadline(std::chrono::steady_clock::now());
  RenderStats stopped;
  EXPECT_FALSE(r.render(image, all, &stopped));
  EXPECT_EQ(image.rgba, blank.rgba);
  // Deadlines a little way off, each stopping somewhere in the frame (in either pass, or not at
  // all on a fast machine); then none: the frame is finished, the hits kept by the rays traced
  // before shaded again, and it is the frame never stopped, byte for byte.
  for (int us : {100, 300, 1000}) {
    r.setDeadline(std::chrono::steady_clock::now() + std::chrono::microseconds(us));
    (void)r.render(image, all);
  }
  r.setDeadline(std::nullopt);
  EXPECT_TRUE(r.render(image, all));
  EXPECT_EQ(image.rgba, expected.rgba);
}

// Without anti-aliasing (the kiosk's coarse pictures) every pixel is one ray through its centre
// and no ring is traced round the spans: the picture differs from the anti-aliased one only at
// its edge pixels, and turning it back on gives the anti-aliased bytes.
TEST(RenderAntialias, OffTracesOneRayAPixelAndDiffersOnlyAtEdges) {
  const GeneratedPiece piece = smallPiece(40, 29);
  auto built = piece.makeModel();
  ASSERT_TRUE(built.ok()) << built.error();
  const Model& model = *built;
  const Camera camera(piece.camera, 240, 160);
  ThreadPool pool(2);
  Renderer r(pool);
  lookAt(r, model, camera);
  Image smooth, plain;
  RenderStats withEdges, without;
  ASSERT_TRUE(r.renderFull(smooth, &withEdges));
  ASSERT_GT(withEdges.edgePixels, 50u);
  r.setAntialias(false);
  ASSERT_TRUE(r.renderFull(plain, &without));
  EXPECT_EQ(without.edgePixels, 0u);
  EXPECT_EQ(without.rays, static_cast<std::uint64_t>(camera.width()) * camera.height());
  // A small rectangle: its own pixels' rays only (traced, or shaded at their kept hits).
  RenderStats small;
  ASSERT_TRUE(r.render(plain, Rect{100, 60, 20, 10}, &small));
  EXPECT_EQ(small.rays + small.reshaded, 200u);
  long differ = 0;
  for (size_t i = 0; i < smooth.rgba.size(); i += 4) differ += std::memcmp(&smooth.rgba[i], &plain.rgba[i], 3) != 0;
  EXPECT_GT(differ, 0);
  EXPECT_LE(differ, static_cast<long>(withEdges.edgePixels));
  r.setAntialias(true);
  Image again;
  ASSERT_TRUE(r.renderFull(again));
  EXPECT_EQ(again.rgba, smooth.rgba);
}

// The kiosk's frame, its preview and its coarse pictures at every scale they take (2 to 16 pixels
// a ray): each size's backdrop is computed once, and going back to any of them computes none (a
// coarse picture at a scale no longer kept spent up to 2 ms of the pen's step on it). The pictures
// are the same bytes as a renderer that saw only their own size.
TEST(RendererBackdrops, EverySizeAKioskTracesAtIsComputedOnce) {
  const GeneratedPiece piece = smallPiece(20, 37);
  auto built = piece.makeModel();
  ASSERT_TRUE(built.ok()) << built.error();
  const Model& model = *built;
  ThreadPool pool(2);
  Renderer r(pool);
  const Camera frame(piece.camera, 640, 400);
  lookAt(r, model, frame);
  EXPECT_EQ(r.backdropsMade(), 1u);
  for (int round = 0; round < 2; ++round)
    for (int scale = 2; scale <= 16; ++scale) {
      r.setCamera(Camera(piece.camera, 640 / scale, 400 / scale));
      r.setCamera(frame);
    }
  EXPECT_EQ(r.backdropsMade(), 16u) << "the frame's and 15 scales', each once";
  // A picture at a kept size is its own size's picture.
  const Camera low(piece.camera, 640 / 5, 400 / 5);
  r.setCamera(low);
  Image kept, fresh;
  ASSERT_TRUE(r.renderFull(kept));
  Renderer alone(pool);
  lookAt(alone, model, low);
  ASSERT_TRUE(alone.renderFull(fresh));
  EXPECT_EQ(kept.rgba, fresh.rgba);
}

TEST(RendererPick, FindsTheModelsSurfaceAndDeclinesWhenBehind) {
  const GeneratedPiece piece = smallPiece(60, 31);
  auto built = piece.makeModel();
  ASSERT_TRUE(built.ok()) << built.error();
  Model& model = *built;
  const Camera camera(piece.camera, 160, 100);
  ThreadPool pool(2);
  Renderer r(pool);
  lookAt(r, model, camera);
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
