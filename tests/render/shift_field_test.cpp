// The set operations' shift fields (the offsets after each, moving its tool with the sheet) follow
// the field's changes without summing them again: an append's values found once on the field's
// lattice, a big region's bands as they land, a live preview's samples put back. Whatever path
// they took, they hold the bits a fresh build's hold.
#include <gtest/gtest.h>

#include <cstring>
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

}  // namespace
}  // namespace emboss
