// The renderer's field follows the model: undoing or replacing the last stroke puts back the
// samples saved before it and appends what follows, and the field is the one a fresh build gives,
// bit for bit.
#include <gtest/gtest.h>

#include <cstring>
#include <string>

#include "bench/piece_generator.h"
#include "render/renderer.h"

namespace emboss {
namespace {

// The first sample where two fields differ, or an empty string.
std::string firstDifference(const HeightField& a, const HeightField& b) {
  if (a.nx() != b.nx() || a.ny() != b.ny()) return "sizes differ";
  for (int j = 0; j < a.ny(); ++j)
    for (int i = 0; i < a.nx(); ++i)
      if (std::memcmp(&a.sample(i, j), &b.sample(i, j), sizeof(HeightField::Sample)) != 0)
        return "sample (" + std::to_string(i) + ", " + std::to_string(j) + ")";
  return {};
}

Operation region(double cx, double cy, double r, int points, double height) {
  Operation o;
  o.kind = OpKind::Region;
  o.side = Side::Back;
  for (int k = 0; k < points; ++k) {
    const double a = 6.283185307179586 * k / points;
    o.points.push_back({cx + r * std::cos(a) * (1.0 + 0.2 * std::sin(3 * a)), cy + r * std::sin(a)});
  }
  o.height = height;
  o.falloff = 2.0;
  return o;
}

TEST(FieldSync, UndoingOrReplacingTheLastStrokeGivesTheFreshlyBuiltField) {
  PieceOptions opt;
  opt.width = 80, opt.height = 60, opt.halfThickness = 0.5;
  const GeneratedPiece piece = generatePiece(60, 17, opt);
  PieceRandom rng(91);
  ThreadPool pool(2);
  Renderer live(pool);
  Model model(piece.workpiece, piece.deformation);
  for (const Operation& o : piece.operations) ASSERT_TRUE(model.add(o).ok());
  live.sync(model);
  for (int round = 0; round < 12; ++round) {
    SCOPED_TRACE("round " + std::to_string(round));
    // A raised region, a punch or a traced segment, then: undone; undone and another one in its
    // place in the same sync (a live preview growing); or kept and undone later.
    const double kind = rng.uniform(0, 1);
    const Operation op = kind < 0.4   ? region(rng.uniform(-25, 25), rng.uniform(-15, 15), rng.uniform(4, 12), 30, 0.8)
                         : kind < 0.7 ? randomPunch(rng, piece, 1.5)
                                      : randomTraceSegment(rng, piece, 1.5);
    ASSERT_TRUE(model.add(op).ok());
    live.sync(model);
    const double what = rng.uniform(0, 1);
    if (what < 0.4) {
      model.undo();
    } else if (what < 0.8) {
      model.undo();
      ASSERT_TRUE(model.add(region(rng.uniform(-25, 25), rng.uniform(-15, 15), rng.uniform(4, 12), 24, -0.6)).ok());
    }
    live.sync(model);
    Model fresh(model.workpiecePtr(), model.deformation());
    for (size_t i = 0; i < model.activeCount(); ++i) ASSERT_TRUE(fresh.add(model.operations()[i].op()).ok());
    Renderer built(pool);
    built.sync(fresh);
    EXPECT_EQ(firstDifference(live.field(), built.field()), "");
  }
}

}  // namespace
}  // namespace emboss
