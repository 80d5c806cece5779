// Outline sheets evaluate their program through tapes specialised per leaf of the column map:
// the picture is exactly the one the whole program gives.
#include <gtest/gtest.h>

#include <cstring>
#include <string>

#include "bench/piece_generator.h"
#include "render/renderer.h"
#include "tools/metal.h"

namespace emboss {
namespace {

Image renderWith(const GeneratedPiece& piece, const Model& model, bool specialised, size_t* memory) {
  ThreadPool pool(2);
  Renderer r(pool);
  r.setCamera(Camera(piece.camera, 160, 120));
  ShadingParams s;
  s.metal = *metalByName("copper");
  s.frontZ = model.workpiece().bounds().z1;
  r.setShading(s);
  RenderOptions o;
  o.specialisedOutline = specialised;
  r.setOptions(o);
  r.sync(model);
  if (memory) *memory = r.memoryBytes();
  Image image;
  r.renderFull(image);
  return image;
}

TEST(OutlineTapes, ThePictureIsTheWholeProgramsByteForByte) {
  for (unsigned seed : {4u, 9u}) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    auto outline = generateOutlinePiece(900, seed, 30.0, 0.5, 40, seed, false);
    ASSERT_TRUE(outline.ok()) << outline.error();
    const GeneratedPiece& piece = *outline;
    Model model(piece.workpiece, piece.deformation);
    for (const Operation& o : piece.operations) ASSERT_TRUE(model.add(o).ok());
    size_t withTapes = 0, without = 0;
    const Image a = renderWith(piece, model, true, &withTapes);
    const Image c = renderWith(piece, model, false, &without);
    ASSERT_EQ(a.width, c.width);
    ASSERT_EQ(a.height, c.height);
    long differing = 0, hits = 0;
    for (int y = 0; y < a.height; ++y)
      for (int x = 0; x < a.width; ++x) {
        differing += std::memcmp(a.pixel(x, y), c.pixel(x, y), 4) != 0;
        hits += a.pixel(x, y)[0] != c.pixel(0, 0)[0];  // not the corner's backdrop: the piece shows
      }
    EXPECT_EQ(differing, 0);
    EXPECT_GT(hits, a.width * a.height / 10) << "the medallion should fill much of the picture";
    // The tapes are counted in what the renderer holds.
    EXPECT_GT(withTapes, 0u);
  }
}

}  // namespace
}  // namespace emboss
