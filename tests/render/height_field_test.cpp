// The cached displacement field: its error against the exact sum, bit-exact incremental updates,
// and conservative bounds.
#include <gtest/gtest.h>

#include <cmath>
#include <algorithm>
#include <cstring>
#include <vector>
#include <numeric>
#include <random>
#include <stdexcept>

#include "bench/piece_generator.h"
#include "render/renderer.h"
#include "render/shading.h"

namespace emboss {
namespace {

GeneratedPiece densePiece(int ops, unsigned seed) {
  PieceOptions opt;
  opt.width = 100, opt.height = 70;  // a third of A4's area, real tool sizes
  return generatePiece(ops, seed, opt);
}

// A dense piece's model and a renderer (2 threads) synced to it: its field built.
struct SyncedPiece {
  SyncedPiece(int ops, unsigned seed) : model(modelOf(densePiece(ops, seed))), renderer(pool) { renderer.sync(model); }
  static Model modelOf(const GeneratedPiece& piece) {
    auto m = piece.makeModel();
    if (!m.ok()) throw std::runtime_error(m.error());
    return std::move(*m);
  }
  Model model;
  ThreadPool pool{2};
  Renderer renderer;
};

Grad exactDisplacement(const Model& m, double x, double y) {
  Grad total(0.0);
  for (size_t i = 0; i < m.activeCount(); ++i) {
    const PreparedOp& op = m.operations()[i];
    if (op.op().isOffset()) total += op.offset(P3<Grad>{Grad(x, 1, 0, 0), Grad(y, 0, 1, 0), Grad(0.0)}, Deformation::Sheet);
  }
  return total;
}

// The error bound documented in docs/rendering.md.
TEST(HeightField, ErrorAgainstTheExactSumIsSmall) {
  const GeneratedPiece piece = densePiece(1200, 5);
  auto model = piece.makeModel();
  ASSERT_TRUE(model.ok());
  ThreadPool pool(2);
  Renderer r(pool);
  r.sync(*model);
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> ux(-50, 50), uy(-35, 35);
  double maxErr = 0, maxSlopeErr = 0, maxD = 0;
  std::vector<double> slopeErrs;
  for (int i = 0; i < 20000; ++i) {
    const double x = ux(rng), y = uy(rng);
    const Grad e = exactDisplacement(*model, x, y);
    double v, gx, gy;
    r.field().valueAndGradient(x, y, v, gx, gy);
    EXPECT_EQ(v, r.displacementAt(x, y));
    maxErr = std::max(maxErr, std::abs(v - e.v));
    maxSlopeErr = std::max(maxSlopeErr, std::hypot(gx - e.dx, gy - e.dy));
    slopeErrs.push_back(std::hypot(gx - e.dx, gy - e.dy));
    maxD = std::max(maxD, std::abs(e.v));
  }
  std::sort(slopeErrs.begin(), slopeErrs.end());
  const double p99 = slopeErrs[slopeErrs.size() * 99 / 100];
  RecordProperty("max_abs_error_mm", std::to_string(maxErr));
  RecordProperty("max_slope_error", std::to_string(maxSlopeErr));
  std::printf("field error: max |D - D_exact| = %.3g mm, |grad D - grad D_exact| max %.3g, 99th percentile %.3g (max |D| %.3g mm)\n",
              maxErr, maxSlopeErr, p99, maxD);
  EXPECT_GT(maxD, 1.0);  // a real relief
  EXPECT_LT(maxErr, 1.5e-3);
  EXPECT_LT(maxSlopeErr, 6e-2);  // at the creases of the narrowest tracers (docs/rendering.md)
  EXPECT_LT(p99, 1e-2);
}

void expectSameSamples(const HeightField& a, const HeightField& b) {
  ASSERT_EQ(a.nx(), b.nx());
  ASSERT_EQ(a.ny(), b.ny());
  for (int j = 0; j < a.ny(); ++j)
    for (int i = 0; i < a.nx(); ++i)
      ASSERT_EQ(0, std::memcmp(&a.sample(i, j), &b.sample(i, j), sizeof(HeightField::Sample))) << "sample " << i << ", " << j;
  // The shading's cavity depth kept per sample: the same bits too.
  for (int j = 0; j < a.ny(); ++j)
    for (int i = 0; i < a.nx(); ++i) {
      const float p = a.cavitySample(i, j), q = b.cavitySample(i, j);
      ASSERT_EQ(0, std::memcmp(&p, &q, sizeof(float))) << "cavity depth at sample " << i << ", " << j;
    }
}

// The very same bounds (of D and its slopes) from two fields over 2000 random boxes in `domain`,
// each side up to `largest` mm.
void expectSameBounds(const HeightField& a, const HeightField& b, const Box2& domain, double largest, std::mt19937& rng) {
  std::uniform_real_distribution<double> x(domain.x0, domain.x1), y(domain.y0, domain.y1), size(0.01, largest);
  for (int k = 0; k < 2000; ++k) {
    const double x0 = x(rng), y0 = y(rng);
    const Box2 box{x0, y0, std::min(domain.x1, x0 + size(rng)), std::min(domain.y1, y0 + size(rng))};
    const HeightField::Bound p = a.bound(box), q = b.bound(box);
    ASSERT_EQ(p.lo, q.lo);
    ASSERT_EQ(p.hi, q.hi);
    ASSERT_EQ(p.gxlo, q.gxlo);
    ASSERT_EQ(p.gxhi, q.gxhi);
    ASSERT_EQ(p.gylo, q.gylo);
    ASSERT_EQ(p.gyhi, q.gyhi);
  }
}

// Appends, undos (recomputed from scratch under the support), redos and replacing the redo tail
// give the very bits of a field built at once.
TEST(HeightField, IncrementalUpdatesEqualAFullBuildBitForBit) {
  const GeneratedPiece piece = densePiece(300, 7);
  ThreadPool pool(2);
  Renderer live(pool);
  Model model(piece.workpiece, piece.deformation);
  live.sync(model);
  PieceRandom rng(3);
  for (size_t k = 0; k < piece.operations.size(); ++k) {
    ASSERT_TRUE(model.add(piece.operations[k]).ok());
    live.sync(model);
    EXPECT_FALSE(live.lastSync().rebuilt);
    if (k % 37 == 36) {
      for (int u = 0; u < 5; ++u) model.undo();
      live.sync(model);
      if (k % 74 == 73) {
        ASSERT_TRUE(model.add(randomPunch(rng, piece)).ok());  // drops the redo tail
      } else {
        for (int u = 0; u < 3; ++u) model.redo();
      }
      live.sync(model);
    }
    if (k % 50 == 0 || k + 1 == piece.operations.size()) {
      Model fresh(piece.workpiece, piece.deformation);
      for (size_t i = 0; i < model.activeCount(); ++i) ASSERT_TRUE(fresh.add(model.operations()[i].op()).ok());
      Renderer full(pool);
      full.sync(fresh);
      ASSERT_TRUE(full.lastSync().rebuilt);
      SCOPED_TRACE("after operation " + std::to_string(k));
      expectSameSamples(live.field(), full.field());
    }
  }
}

// A point's cell and basis found once on a lattice give every field on that lattice (its own, and
// one configureOn() it over a part of it) the value value(x, y) gives, bit for bit: inside, on its
// cells' edges, and beyond its samples (where the cell is clamped).
TEST(HeightField, ALatticePointGivesEachFieldOnTheLatticeItsOwnValue) {
  const GeneratedPiece piece = densePiece(80, 5);
  const Model model = SyncedPiece::modelOf(piece);
  HeightField whole, part;
  whole.configure(Box2{-50.0, -35.0, 50.0, 35.0}, 0.125);
  part.configureOn(whole, Box2{-12.3, -8.1, 17.9, 11.4});
  for (size_t i = 0; i < model.activeCount(); ++i) {
    const PreparedOp& op = model.operations()[i];
    if (!op.op().isOffset()) continue;
    whole.add(op), part.add(op);
  }
  whole.finish(whole.all()), part.finish(part.all());
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> x(-55.0, 55.0), y(-40.0, 40.0), near(-0.2, 0.2);
  int inPart = 0, beyondPart = 0;
  for (int k = 0; k < 20000; ++k) {
    double px = x(rng), py = y(rng);
    if (k % 4 == 1) px = whole.sampleX(static_cast<int>((px + 50.0) * 8.0) % whole.nx());  // on a cell's edge
    if (k % 4 == 2) px = part.domain().x0 + near(rng), py = part.domain().y1 + near(rng);  // at part's edge
    const HeightField::LatticePoint lp = whole.latticePoint(px, py);
    for (const HeightField* f : {&whole, &part}) {
      const double a = f->value(lp), b = f->value(px, py);
      ASSERT_EQ(std::memcmp(&a, &b, sizeof a), 0) << (f == &part ? "part" : "whole") << " at " << px << ", " << py;
    }
    (part.contains(px, py) ? inPart : beyondPart) += 1;
  }
  EXPECT_GT(inPart, 1000);
  EXPECT_GT(beyondPart, 1000);
}

// A bare sheet's field made without visiting its samples (finishFlat) is the field a full build
// makes: the same samples and, for any box, the very same bounds.
TEST(HeightField, FlatFinishEqualsAFullBuildOfABareSheet) {
  const Box2 domain{-152.5, -107.5, 152.5, 107.5};  // an A4 plate and its margin
  HeightField built, flat;
  built.configure(domain, 0.125, /*cavity=*/true);
  built.recompute(built.all(), {});
  built.finish(built.all());
  flat.configure(domain, 0.125, /*cavity=*/true);
  flat.finishFlat();
  expectSameSamples(flat, built);
  std::mt19937 rng(5);
  expectSameBounds(flat, built, domain, 80.0, rng);
  const HeightField::Bound whole = flat.bound(domain);
  EXPECT_LE(whole.lo, 0.0);
  EXPECT_GE(whole.hi, 0.0);
}

// A field made flat, then added to by a few offsets and finished over the samples they reach (a
// set operation's shift field made when the first offset follows its pile) holds the samples and
// gives the bounds of one summed over every sample and finished everywhere.
TEST(HeightField, AFlatFieldAddedToWhereOffsetsReachEqualsOneSummedEverywhere) {
  const GeneratedPiece piece = densePiece(120, 11);
  const Model model = SyncedPiece::modelOf(piece);
  HeightField lattice;
  lattice.configure(Box2{-55.0, -40.0, 55.0, 40.0}, 0.125);
  std::vector<const PreparedOp*> offsets;
  for (size_t i = 0; i < model.activeCount(); ++i)
    if (model.operations()[i].op().isOffset()) offsets.push_back(&model.operations()[i]);
  ASSERT_GT(offsets.size(), 40u);
  const Box2 domain{-21.7, -13.2, 18.4, 15.9};
  std::mt19937 rng(13);
  for (const size_t n : {size_t{1}, size_t{3}, size_t{12}}) {
    // n offsets, some of whose supports reach past the field or miss it.
    std::vector<const PreparedOp*> after;
    for (size_t k = 0; k < n; ++k) after.push_back(offsets[rng() % offsets.size()]);
    std::sort(after.begin(), after.end());
    after.erase(std::unique(after.begin(), after.end()), after.end());
    HeightField summed, added;
    summed.configureOn(lattice, domain);
    summed.recompute(summed.all(), after);
    summed.finish(summed.all());
    added.configureOn(lattice, domain);
    added.finishFlat();
    HeightField::SampleRect touched;
    for (const PreparedOp* op : after) {
      added.add(*op, added.all());
      touched = HeightField::unite(touched, added.samplesIn(op->support()));
    }
    ASSERT_FALSE(touched.empty());
    ASSERT_LT(touched.count(), added.all().count()) << "the offsets reach part of the field";
    added.finish(touched);
    SCOPED_TRACE(std::to_string(after.size()) + " offsets");
    expectSameSamples(added, summed);
    expectSameBounds(added, summed, domain, 30.0, rng);
  }
}

// The cavity depth the field keeps per sample and interpolates is the shading's ring of six
// (shading.h, cavityAt) over the bilinear D, within a small part of the depth that darkens by half,
// inside the lattice and at its edges (where the ring is clamped to the domain), and the fields
// the renderer makes keep it; the set operations' shift fields do not.
TEST(HeightField, CavityDepthIsTheRingOfSixAroundEachPoint) {
  const SyncedPiece p(600, 11);
  const HeightField& f = p.renderer.field();
  ASSERT_GT(f.cavityReachSamples(), 0);
  const Box2 dom = f.domain();
  std::mt19937 rng(2);
  std::uniform_real_distribution<double> ux(dom.x0, dom.x1), uy(dom.y0, dom.y1), edge(0.0, 1.5);
  double worst = 0, deepest = 0;
  long deep = 0;
  std::vector<double> diffs;
  for (int k = 0; k < 40000; ++k) {
    double x = ux(rng), y = uy(rng);
    if (k % 4 == 0) x = k % 8 == 0 ? dom.x0 + edge(rng) : dom.x1 - edge(rng);  // the ring clamped
    const double ring = cavityAt(x, y, [&](double a, double b) { return f.valueBilinear(a, b); });
    const double kept = cavityOfDepth(f.cavityDepth(x, y));
    worst = std::max(worst, std::abs(kept - ring));
    diffs.push_back(std::abs(kept - ring));
    deepest = std::max(deepest, ring);
    if (ring > 0.3) ++deep;
  }
  std::sort(diffs.begin(), diffs.end());
  const double p99 = diffs[diffs.size() * 99 / 100];
  std::printf("cavity term: kept per sample against the ring of six: max difference %.3g, 99th percentile %.3g "
              "(deepest %.3g, %ld points over 0.3)\n", worst, p99, deepest, deep);
  EXPECT_GT(deep, 100);  // the piece has grooves the term finds
  EXPECT_LT(worst, 0.05);  // at the creases of the narrowest grooves (the term is 0..1)
  EXPECT_LT(p99, 0.005);
}

// The pyramid's bounds hold the interpolated field and its slopes everywhere in their box.
TEST(HeightField, BoundsAreConservative) {
  const SyncedPiece p(600, 9);
  const HeightField& f = p.renderer.field();
  std::mt19937 rng(2);
  std::uniform_real_distribution<double> ux(-50, 50), uy(-35, 35), size(0.0, 3.0), u01(0, 1);
  int tighter = 0;
  for (int i = 0; i < 3000; ++i) {
    const double x = ux(rng), y = uy(rng);
    const Box2 box{x, y, x + size(rng) * size(rng), y + size(rng) * size(rng)};
    // The pyramid's bounds, and the leaves' under the box (within them: never looser).
    const HeightField::Bound coarse = f.bound(box), fine = f.leafBound(box);
    ASSERT_GE(fine.lo, coarse.lo);
    ASSERT_LE(fine.hi, coarse.hi);
    tighter += fine.hi - fine.lo < coarse.hi - coarse.lo;
    for (const HeightField::Bound& b : {coarse, fine})
      for (int k = 0; k < 30; ++k) {
        const double px = box.x0 + u01(rng) * (box.x1 - box.x0), py = box.y0 + u01(rng) * (box.y1 - box.y0);
        double v, gx, gy;
        f.valueAndGradient(px, py, v, gx, gy);
        ASSERT_GE(v, b.lo);
        ASSERT_LE(v, b.hi);
        ASSERT_GE(gx, b.gxlo);
        ASSERT_LE(gx, b.gxhi);
        ASSERT_GE(gy, b.gylo);
        ASSERT_LE(gy, b.gyhi);
      }
  }
  // (Boxes over a few leaves: the leaves' bounds are tighter for some.)
  EXPECT_GT(tighter, 100);
}

// The field is a function of the model alone: the same numbers in every sync order.
TEST(HeightField, LatticeDependsOnTheWorkpieceOnly) {
  const GeneratedPiece piece = densePiece(50, 11);
  auto model = piece.makeModel();
  ASSERT_TRUE(model.ok());
  ThreadPool pool(1);
  Renderer a(pool), b(pool);
  Model empty(piece.workpiece, piece.deformation);
  a.sync(empty);
  b.sync(*model);
  EXPECT_EQ(a.field().domain().x0, b.field().domain().x0);
  EXPECT_EQ(a.field().spacing(), b.field().spacing());
  EXPECT_LE(a.field().spacing(), 0.125);
}

}  // namespace
}  // namespace emboss
