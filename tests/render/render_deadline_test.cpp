// A render with a deadline stops there, as a cancelled one does, and the rays it traced before
// keep their hits: the render after it gives the bytes of a render never stopped.
#include <gtest/gtest.h>

#include <chrono>

#include "bench/piece_generator.h"
#include "render/renderer.h"
#include "render/shading.h"

namespace emboss {
namespace {

TEST(RenderDeadline, AStoppedRenderIsFinishedByTheNextToTheSameBytes) {
  PieceOptions opt;
  opt.width = 60, opt.height = 40, opt.halfThickness = 0.5;
  const GeneratedPiece piece = generatePiece(40, 23, opt);
  auto built = piece.makeModel();
  ASSERT_TRUE(built.ok()) << built.error();
  const Model& model = *built;
  const Camera camera(piece.camera, 240, 160);
  ThreadPool pool(2);

  Renderer reference(pool);
  reference.setCamera(camera);
  reference.setShading(sheetShading("copper", "none", model.workpiece().bounds().z1));
  reference.sync(model);
  Image expected;
  ASSERT_TRUE(reference.renderFull(expected));

  Renderer r(pool);
  RenderOptions o;
  o.reuseHits = true;
  r.setOptions(o);
  r.setCamera(camera);
  r.setShading(sheetShading("copper", "none", model.workpiece().bounds().z1));
  r.sync(model);
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

}  // namespace
}  // namespace emboss
