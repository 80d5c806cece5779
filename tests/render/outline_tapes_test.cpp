// Outline sheets evaluate their program through tapes specialised per leaf of the column map:
// the picture is exactly the one the whole program gives.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <stdexcept>
#include <string>

#include "bench/piece_generator.h"
#include "render/renderer.h"
#include "tools/metal.h"

namespace emboss {
namespace {

Image renderWith(const GeneratedPiece& piece, const Model& model, bool specialised, size_t* memory, bool scanCells = true,
                 int width = 160, int height = 120, RenderStats* stats = nullptr) {
  ThreadPool pool(2);
  Renderer r(pool);
  r.setCamera(Camera(piece.camera, width, height));
  ShadingParams s;
  s.metal = *metalByName("copper");
  s.frontZ = model.workpiece().bounds().z1;
  r.setShading(s);
  RenderOptions o;
  o.specialisedOutline = specialised;
  o.scanOutlineCells = scanCells;
  r.setOptions(o);
  r.sync(model);
  if (memory) *memory = r.memoryBytes();
  Image image;
  r.renderFull(image, stats);
  return image;
}

// The test's 900-clause medallion (its strokes not added) synced by a renderer of 160 x 120.
struct SyncedOutline {
  SyncedOutline() : piece(medallion()), model(piece.workpiece, piece.deformation), renderer(pool) {
    renderer.setCamera(Camera(piece.camera, 160, 120));
    renderer.sync(model);
    bounds = model.workpiece().bounds(), d = model.workpiece().halfThickness();
  }
  static GeneratedPiece medallion() {
    auto outline = generateOutlinePiece(900, 4, 30.0, 0.5, 40, 4, false);
    if (!outline.ok()) throw std::runtime_error(outline.error());
    return std::move(*outline);
  }
  GeneratedPiece piece;
  Model model;
  ThreadPool pool{2};
  Renderer renderer;
  Box3 bounds;
  double d = 0;  // the sheet's half thickness
};

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

// Where the outline crosses or comes near a column block, the block's sub-cells have bounds of
// their own: min(O, d) at every point lies within its sub-cell's (W at z' = 0), which are never
// wider than the block's, and many sub-cells decide W (outside, or the slab) where their block
// does not, so the walk needs the outline's program only in the sub-cells the outline crosses.
TEST(OutlineTapes, CellsNearTheOutlineScannedPointByPointGiveTheBisectionsPicture) {
  // A cell whose interval test failed near the outline's wall: its points one by one or its halves
  // bisected, the first point with f >= 0 and the secant to it are the same.
  auto outline = generateOutlinePiece(900, 9, 30.0, 0.5, 40, 9, true);
  ASSERT_TRUE(outline.ok()) << outline.error();
  const GeneratedPiece& piece = *outline;
  Model model(piece.workpiece, piece.deformation);
  for (const Operation& o : piece.operations) ASSERT_TRUE(model.add(o).ok());
  RenderStats scanned, bisected;
  const Image a = renderWith(piece, model, true, nullptr, true, 480, 360, &scanned);
  const Image b = renderWith(piece, model, true, nullptr, false, 480, 360, &bisected);
  long differing = 0;
  for (int y = 0; y < a.height; ++y)
    for (int x = 0; x < a.width; ++x) differing += std::memcmp(a.pixel(x, y), b.pixel(x, y), 4) != 0;
  EXPECT_EQ(differing, 0);
  // The two searches took other ways there (else the scan was never tried).
  EXPECT_NE(scanned.evaluations, bisected.evaluations);
  EXPECT_EQ(scanned.hits, bisected.hits);
}

TEST(OutlineTapes, SubCellsBoundTheOutlineAndDecideWhereTheirBlockDoesNot) {
  const SyncedOutline m;
  PieceRandom rng(23);
  int inSub = 0, decidedBySub = 0;
  for (int i = 0; i < 200000 && inSub < 4000; ++i) {
    const double x = rng.uniform(m.bounds.x0 - 1.0, m.bounds.x1 + 1.0), y = rng.uniform(m.bounds.y0 - 1.0, m.bounds.y1 + 1.0);
    const Renderer::ColumnBounds c = m.renderer.columnBoundsAt(x, y);
    const double v = m.model.workpiece().value(P3<double>{x, y, 0.0});  // min(O, d)
    const double eps = 1e-9 * (1.0 + std::abs(v));
    // The conventions of both: hi < 0 outside (lo then -inf); lo = 2d where O >= d.
    ASSERT_LE(v, c.hi + eps) << x << ", " << y;
    ASSERT_GE(v, std::min<double>(c.lo, m.d) - eps) << x << ", " << y;
    if (!c.sub) {
      ASSERT_EQ(c.lo, c.blockLo);
      ASSERT_EQ(c.hi, c.blockHi);
      continue;
    }
    ++inSub;
    ASSERT_LE(c.hi, c.blockHi);
    if (c.hi >= 0.0f) {  // (an outside sub-cell's lo is -inf)
      ASSERT_GE(c.lo, c.blockLo);
    }
    const bool blockDecides = c.blockHi < 0.0f || c.blockLo >= static_cast<float>(m.d);
    EXPECT_FALSE(blockDecides) << "only blocks the outline crosses or comes near have sub-cells";
    decidedBySub += c.hi < 0.0f || c.lo >= static_cast<float>(m.d);
  }
  EXPECT_GE(inSub, 1000) << "the medallion's outline should cross many blocks";
  EXPECT_GT(decidedBySub, inSub / 4) << "sub-cells should decide W at many points their block leaves open";
}

// A box across the edges of leaves or regions is bounded by the hull of its parts, each through
// its own cell's tape: every value of W in the box lies within it, and it is never wider than
// the whole program's interval over the box. (Most random boxes lie where the slab or the outside
// decides W, the same interval either way; the rest are narrower.)
TEST(OutlineTapes, ABoxAcrossCellsIsBoundedByItsPartsTapes) {
  const SyncedOutline m;
  const Renderer& r = m.renderer;
  const Workpiece& w = m.model.workpiece();
  const Box3& b = m.bounds;
  const double d = m.d;
  PieceRandom rng(17);
  int narrower = 0, boxes = 0;
  for (int i = 0; i < 400; ++i) {
    // Half-sizes from a twentieth of a block to beyond a region (0.01 to 12 mm).
    const double hx = 0.01 * std::pow(1200.0, rng.uniform(0.0, 1.0)), hy = 0.01 * std::pow(1200.0, rng.uniform(0.0, 1.0));
    const double cx = rng.uniform(b.x0, b.x1), cy = rng.uniform(b.y0, b.y1), cz = rng.uniform(-d, d);
    const P3<Interval> box{Interval(cx - hx, cx + hx), Interval(cy - hy, cy + hy), Interval(cz - 0.1 * d, cz + 0.1 * d)};
    const Interval v = r.workpieceBound(box);
    const Interval whole = w.value(box);
    const double eps = 1e-9 * (1.0 + std::abs(whole.lo) + std::abs(whole.hi));
    ++boxes;
    ASSERT_GE(v.lo, whole.lo - eps) << "box " << i;
    ASSERT_LE(v.hi, whole.hi + eps) << "box " << i;
    narrower += v.hi - v.lo < 0.99 * (whole.hi - whole.lo);
    for (int k = 0; k < 25; ++k) {
      const P3<double> p{rng.uniform(box.x.lo, box.x.hi), rng.uniform(box.y.lo, box.y.hi), rng.uniform(box.z.lo, box.z.hi)};
      const double f = w.value(p);
      ASSERT_GE(f, v.lo - eps) << "box " << i << " point " << k;
      ASSERT_LE(f, v.hi + eps) << "box " << i << " point " << k;
    }
  }
  EXPECT_GT(narrower, boxes / 10) << "the parts' tapes should bound the boxes near the outline tighter than the whole program";
}

}  // namespace
}  // namespace emboss
