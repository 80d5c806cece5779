// The set operations' shift fields (the offsets after each, moving its tool with the sheet) follow
// the field's changes without summing them again: an append's values found once on the field's
// lattice, a big region's bands as they land, a live preview's samples put back. Whatever path
// they took, they hold the bits a fresh build's hold.
#include <gtest/gtest.h>

#include <cstring>
#include <set>
#include <string>

#include "bench/piece_generator.h"
#include "render/renderer.h"

namespace emboss {
namespace {

Model rebuilt(const Model& live) {
  Model m(live.workpiecePtr(), live.deformation());
  for (size_t i = 0; i < live.activeCount(); ++i) EXPECT_TRUE(m.add(live.operations()[i].op()).ok());
  return m;
}

// The first shift field sample that differs between two renderers, or an empty string.
std::string firstDifference(const Renderer& a, const Renderer& b) {
  if (a.setOperationCount() != b.setOperationCount()) return "the set operations differ";
  for (size_t k = 0; k < a.setOperationCount(); ++k) {
    const HeightField* fa = a.shiftField(k);
    const HeightField* fb = b.shiftField(k);
    if (!fa || !fb) {
      if (fa != fb) return "set operation " + std::to_string(k) + ": one shift field missing";
      continue;
    }
    if (fa->nx() != fb->nx() || fa->ny() != fb->ny() || fa->sampleX(0) != fb->sampleX(0) || fa->sampleY(0) != fb->sampleY(0))
      return "set operation " + std::to_string(k) + ": another lattice";
    for (int j = 0; j < fa->ny(); ++j)
      for (int i = 0; i < fa->nx(); ++i)
        if (std::memcmp(&fa->sample(i, j), &fb->sample(i, j), sizeof(HeightField::Sample)) != 0)
          return "set operation " + std::to_string(k) + ", sample (" + std::to_string(i) + ", " + std::to_string(j) +
                 "): D " + std::to_string(fa->sample(i, j).d) + " against " + std::to_string(fb->sample(i, j).d);
  }
  return {};
}

std::string firstPixelDifference(const Image& a, const Image& b) {
  for (int y = 0; y < a.height; ++y)
    for (int x = 0; x < a.width; ++x)
      if (std::memcmp(a.pixel(x, y), b.pixel(x, y), 4) != 0) return "pixel (" + std::to_string(x) + ", " + std::to_string(y) + ")";
  return {};
}

// A punch from behind at (x, y), of the same size each time.
Operation punchAt(double x, double y) {
  Operation o;
  o.kind = OpKind::Punch;
  o.a = 1.8, o.p = 0.4, o.q = 1.0;
  o.at = {x, y, 0.0};
  return o;
}

bool overlapsASetOperation(const Operation& o, const Model& model) {
  const Box2 s = PreparedOp(o).support();
  for (size_t i = 0; i < model.activeCount(); ++i)
    if (model.operations()[i].op().isSet() && model.operations()[i].support().overlaps(s)) return true;
  return false;
}

TEST(ShiftFields, FollowTheFieldToTheBitsOfAFreshBuild) {
  PieceOptions opt;
  opt.width = 48, opt.height = 36;
  opt.halfThickness = 0.5;
  opt.toolScale = 1.6;
  GeneratedPiece piece = generatePiece(10, 31, opt);
  PieceRandom rng(53);
  for (int k = 0; k < 14; ++k) piece.operations.push_back(randomSetOperation(rng, piece, opt.toolScale));
  ThreadPool pool(2), onePool(1);
  Renderer live(pool);
  Model model(piece.workpiece, piece.deformation);
  for (const Operation& op : piece.operations) ASSERT_TRUE(model.add(op).ok());
  const Camera camera(piece.camera, 128, 80);
  live.setCamera(camera);
  RenderOptions options;
  options.fieldBandMs = 1e-6;  // a big region comes eight rows a call
  live.setOptions(options);
  live.sync(model);
  ASSERT_GE(live.setOperationCount(), 14u);

  const auto check = [&](const std::string& what) {
    Renderer fresh(onePool);
    fresh.setCamera(camera);
    const Model m = rebuilt(model);
    fresh.sync(m);
    const std::string diff = firstDifference(live, fresh);
    EXPECT_TRUE(diff.empty()) << what << ": " << diff;
  };
  // A stroke or region over at least one set operation (a region that more than a few bands hold).
  const auto over = [&](auto make, long leastSamples) {
    for (;;) {
      Operation o = make();
      if (overlapsASetOperation(o, model) && live.field().samplesIn(PreparedOp(o).support()).count() >= leastSamples) return o;
    }
  };
  const long big = 5 * Renderer::kFieldBandMinSamples;
  const auto region = [&] { return over([&] { return randomRegion(rng, piece, opt.toolScale); }, big); };
  const auto punch = [&] { return over([&] { return randomPunch(rng, piece, opt.toolScale); }, 1); };
  const auto finishBands = [&] {
    while (live.fieldPending()) live.continueField(options.fieldBandMs);
  };

  // A big region, a band at a time: the shift fields under it take each band's values.
  ASSERT_TRUE(model.add(region()).ok());
  live.sync(model);
  ASSERT_TRUE(live.fieldPending());
  finishBands();
  EXPECT_GT(live.lastSync().shiftSamplesShared, 0);
  EXPECT_EQ(live.lastSync().shiftSamplesComputed, 0);
  check("a region added in bands");

  // A punch: its values found once, whole.
  ASSERT_TRUE(model.add(punch()).ok());
  live.sync(model);
  EXPECT_GT(live.lastSync().shiftSamplesShared, 0);
  check("a punch");

  // A live preview replaced twice: the shift fields put back what they had under it.
  for (int k = 0; k < 2; ++k) {
    ASSERT_TRUE(model.undo());
    ASSERT_TRUE(model.add(punch()).ok());
    live.sync(model);
    check("a preview replaced");
  }

  // A set operation and a big region in one sync: the new shift field takes the region's rows
  // added so far, then the next bands.
  ASSERT_TRUE(model.add(randomSetOperation(rng, piece, opt.toolScale)).ok());
  ASSERT_TRUE(model.add(region()).ok());
  live.sync(model);
  ASSERT_TRUE(live.fieldPending());
  live.continueField(options.fieldBandMs);
  finishBands();
  check("a set operation made while a region was pending");

  // A stroke while a region's bands are pending: its other rows first.
  ASSERT_TRUE(model.add(region()).ok());
  live.sync(model);
  ASSERT_TRUE(live.fieldPending());
  live.continueField(options.fieldBandMs);
  ASSERT_TRUE(model.add(punch()).ok());
  live.sync(model);
  EXPECT_FALSE(live.fieldPending());
  check("a punch while a region was pending");

  // A pending region undone, and one replaced by a punch in the same sync.
  ASSERT_TRUE(model.add(region()).ok());
  live.sync(model);
  live.continueField(options.fieldBandMs);
  ASSERT_TRUE(model.undo());
  live.sync(model);
  check("a pending region undone");
  ASSERT_TRUE(model.add(region()).ok());
  live.sync(model);
  live.continueField(options.fieldBandMs);
  ASSERT_TRUE(model.undo());
  ASSERT_TRUE(model.add(punch()).ok());
  live.sync(model);
  finishBands();
  check("a pending region replaced by a punch");

  // And the picture is a fresh render's.
  Image a, b;
  live.renderFull(a);
  Renderer fresh(onePool);
  fresh.setCamera(camera);
  const Model m = rebuilt(model);
  fresh.sync(m);
  fresh.renderFull(b);
  EXPECT_EQ(firstPixelDifference(a, b), "");
}

// A run of set operations (no offset between them) holds one shift: wherever two of their
// supports meet, their shift fields give the same bits, which fieldValue() reads once a run. A
// set operation after an offset (another run) does not: the offset between moves the first
// run's tools and not its own.
TEST(ShiftFields, ARunsSetOperationsHoldTheSameBitsWhereTheirSupportsMeet) {
  PieceOptions opt;
  opt.width = 48, opt.height = 36;
  opt.halfThickness = 0.5;
  GeneratedPiece piece = generatePiece(10, 31, opt);
  PieceRandom rng(71);
  const Vec2 pile{3.0, -2.0};
  // Beads piled within 2 mm of one point, a punch under the pile between the two runs, then
  // punches over it (the offsets after each, whose sum is the shift).
  const auto bead = [&] {
    Operation o = randomSetOperation(rng, piece);
    o.tool.center.x = pile.x + rng.uniform(-2.0, 2.0), o.tool.center.y = pile.y + rng.uniform(-2.0, 2.0);
    return o;
  };
  const auto punchNear = [&](double dx, double dy) { return punchAt(pile.x + dx, pile.y + dy); };
  ThreadPool pool(2);
  Renderer live(pool);
  Model model(piece.workpiece, piece.deformation);
  for (const Operation& op : piece.operations) ASSERT_TRUE(model.add(op).ok());
  live.setCamera(Camera(piece.camera, 64, 40));
  live.sync(model);
  const size_t first = live.setOperationCount();
  for (int k = 0; k < 6; ++k) ASSERT_TRUE(model.add(bead()).ok());
  ASSERT_TRUE(model.add(punchNear(1.0, 0.5)).ok());
  for (int k = 0; k < 4; ++k) ASSERT_TRUE(model.add(bead()).ok());
  live.sync(model);  // (the shift fields made afresh)
  for (int k = 0; k < 5; ++k) ASSERT_TRUE(model.add(punchNear(rng.uniform(-3.0, 3.0), rng.uniform(-3.0, 3.0))).ok());
  live.sync(model);  // (and following the punches)
  ASSERT_EQ(live.setOperationCount(), first + 10);

  std::vector<Box2> supports;
  for (size_t i = 0; i < model.activeCount(); ++i)
    if (model.operations()[i].op().isSet()) supports.push_back(model.operations()[i].support());
  // Compares set operations a and b at points where both supports hold: the count of points whose
  // value or gradient differ in a bit, of `n` tried.
  const auto differing = [&](size_t a, size_t b, int n) {
    const Box2 both = supports[a].intersected(supports[b]);
    EXPECT_FALSE(both.empty());
    int count = 0;
    for (int k = 0; k < n; ++k) {
      const double x = rng.uniform(both.x0, both.x1), y = rng.uniform(both.y0, both.y1);
      double va, gxa, gya, vb, gxb, gyb;
      live.shiftField(a)->valueAndGradient(x, y, va, gxa, gya);
      live.shiftField(b)->valueAndGradient(x, y, vb, gxb, gyb);
      const double pa[4] = {live.shiftField(a)->value(x, y), va, gxa, gya};
      const double pb[4] = {live.shiftField(b)->value(x, y), vb, gxb, gyb};
      count += std::memcmp(pa, pb, sizeof pa) != 0;
    }
    return count;
  };
  for (size_t a = first; a < first + 6; ++a)
    for (size_t b = a + 1; b < first + 6; ++b) EXPECT_EQ(differing(a, b, 400), 0) << "the first run: " << a << ", " << b;
  for (size_t a = first + 6; a < first + 10; ++a)
    for (size_t b = a + 1; b < first + 10; ++b) EXPECT_EQ(differing(a, b, 400), 0) << "the second run: " << a << ", " << b;
  // Across the punch between them: the first run's shift holds it.
  EXPECT_GT(differing(first, first + 6, 400), 100);

  // And the picture is a fresh render's after the last punch is undone and replaced (the fields
  // put back and followed).
  ASSERT_TRUE(model.undo());
  ASSERT_TRUE(model.add(punchNear(-1.0, 1.0)).ok());
  live.sync(model);
  Image a, b;
  live.renderFull(a);
  Renderer fresh(pool);
  fresh.setCamera(Camera(piece.camera, 64, 40));
  const Model m = rebuilt(model);
  fresh.sync(m);
  fresh.renderFull(b);
  EXPECT_EQ(firstDifference(live, fresh), "");
  EXPECT_EQ(firstPixelDifference(a, b), "");
}

// A run's set operations piled together share one shift field once an offset follows them (the
// pile's dozens of fields were each given every offset under it); until then each keeps its own,
// all zeros. A trail across the sheet is not one field. Whatever they share, the fields and the
// picture are a fresh build's.
TEST(ShiftFields, APilesSetOperationsShareOneFieldOnceAnOffsetFollowsThem) {
  PieceOptions opt;
  opt.width = 60, opt.height = 40;
  opt.halfThickness = 0.5;
  GeneratedPiece piece = generatePiece(10, 37, opt);
  PieceRandom rng(83);
  const Vec2 pile{-8.0, 2.0};
  const auto beadAt = [&](double x, double y) {
    Operation o = randomSetOperation(rng, piece);
    o.tool.center.x = x, o.tool.center.y = y;
    return o;
  };
  ThreadPool pool(2), onePool(1);
  Renderer live(pool);
  Model model(piece.workpiece, piece.deformation);
  for (const Operation& op : piece.operations) ASSERT_TRUE(model.add(op).ok());
  const Camera camera(piece.camera, 96, 64);
  live.setCamera(camera);
  live.sync(model);
  const size_t first = live.setOperationCount();
  // The pile, bead by bead as a visitor beats it: nothing follows it yet.
  constexpr size_t kPile = 12;
  for (size_t k = 0; k < kPile; ++k) {
    ASSERT_TRUE(model.add(beadAt(pile.x + rng.uniform(-2.0, 2.0), pile.y + rng.uniform(-2.0, 2.0))).ok());
    live.sync(model);
  }
  ASSERT_EQ(live.setOperationCount(), first + kPile);
  const auto fields = [&](size_t from, size_t n) {
    std::set<const HeightField*> f;
    for (size_t k = from; k < from + n; ++k) f.insert(live.shiftField(k));
    return f.size();
  };
  const auto check = [&](const std::string& what) {
    Renderer fresh(onePool);
    fresh.setCamera(camera);
    const Model m = rebuilt(model);
    fresh.sync(m);
    EXPECT_EQ(firstDifference(live, fresh), "") << what;
    Image a, b;
    live.renderFull(a);
    fresh.renderFull(b);
    EXPECT_EQ(firstPixelDifference(a, b), "") << what;
  };
  EXPECT_EQ(fields(first, kPile), kPile) << "an open run";
  check("the pile");

  // A punch under the pile: one field for it, made with the punch; the next punches are added
  // to that one field, once.
  ASSERT_TRUE(model.add(punchAt(pile.x + 1.0, pile.y - 0.5)).ok());
  live.sync(model);
  EXPECT_EQ(fields(first, kPile), 1u) << "the first offset after the pile";
  const HeightField* shared = live.shiftField(first);
  check("a punch under the pile");
  ASSERT_TRUE(model.add(punchAt(pile.x - 1.5, pile.y + 1.0)).ok());
  live.sync(model);
  EXPECT_EQ(live.shiftField(first), shared) << "kept";
  const long once = static_cast<long>(shared->nx()) * shared->ny();
  EXPECT_GT(live.lastSync().shiftSamplesShared + live.lastSync().shiftSamplesComputed, 0);
  EXPECT_LE(live.lastSync().shiftSamplesShared + live.lastSync().shiftSamplesComputed, once);
  check("a second punch under the pile");

  // A live preview replaced: the shared field puts back what it had under the punch.
  ASSERT_TRUE(model.undo());
  ASSERT_TRUE(model.add(punchAt(pile.x - 0.5, pile.y + 1.5)).ok());
  live.sync(model);
  EXPECT_EQ(live.shiftField(first), shared);
  check("a preview replaced over the pile");

  // Both punches undone: the run is open again, a field for each; redone: one again.
  ASSERT_TRUE(model.undo());
  ASSERT_TRUE(model.undo());
  live.sync(model);
  EXPECT_EQ(fields(first, kPile), kPile) << "the offsets after the pile undone";
  check("the punches undone");
  ASSERT_TRUE(model.redo());
  live.sync(model);
  EXPECT_EQ(fields(first, kPile), 1u);
  check("a punch redone");

  // A trail of beads along a diagonal, 9 mm apart, then a punch under it: the box of all of them
  // would be mostly empty, so they are not one field.
  constexpr size_t kTrail = 5;
  const size_t trail = live.setOperationCount();
  for (size_t k = 0; k < kTrail; ++k) ASSERT_TRUE(model.add(beadAt(-18.0 + 9.0 * k, -16.0 + 9.0 * k)).ok());
  ASSERT_TRUE(model.add(punchAt(0.0, 2.0)).ok());
  live.sync(model);
  EXPECT_GT(fields(trail, kTrail), 1u) << "a trail";
  EXPECT_LT(fields(trail, kTrail), kTrail) << "neighbours along the trail";
  check("a trail");
}

}  // namespace
}  // namespace emboss
