// The operation grid: candidates are exactly a superset of the operations whose support holds
// the point, ascending and active only, through adds, undos, redos and replaced redo tails.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "bench/piece_generator.h"
#include "frep/op_grid.h"

namespace emboss {
namespace {

// `keep`: the operations the grid lists (all when null); it must list no other.
void checkAt(const OpGrid& grid, const Model& m, std::mt19937& rng, OpGrid::Filter keep = nullptr) {
  std::uniform_real_distribution<double> ux(-60, 60), uy(-45, 45);
  std::vector<std::uint32_t> scratch;
  for (int k = 0; k < 200; ++k) {
    const double x = ux(rng), y = uy(rng);
    const auto c = grid.at(x, y, scratch);
    ASSERT_TRUE(std::is_sorted(c.begin(), c.end()));
    for (std::uint32_t i : c) {
      ASSERT_LT(i, m.activeCount());
      if (keep) ASSERT_TRUE(keep(m.operations()[i].op())) << "operation " << i;
    }
    for (size_t i = 0; i < m.activeCount(); ++i) {
      if ((!keep || keep(m.operations()[i].op())) && m.operations()[i].support().contains(x, y)) {
        ASSERT_TRUE(std::binary_search(c.begin(), c.end(), static_cast<std::uint32_t>(i))) << "operation " << i;
      }
    }
    const Box2 box{x, y, x + 3.0, y + 1.5};
    const auto in = grid.in(box, scratch);
    ASSERT_TRUE(std::is_sorted(in.begin(), in.end()));
    ASSERT_TRUE(std::adjacent_find(in.begin(), in.end()) == in.end());
    for (std::uint32_t i : in)
      if (keep) ASSERT_TRUE(keep(m.operations()[i].op())) << "operation " << i;
    for (size_t i = 0; i < m.activeCount(); ++i) {
      if ((!keep || keep(m.operations()[i].op())) && m.operations()[i].support().overlaps(box)) {
        ASSERT_TRUE(std::binary_search(in.begin(), in.end(), static_cast<std::uint32_t>(i))) << "operation " << i;
      }
    }
  }
}

TEST(OpGrid, FollowsEditsIncrementally) {
  PieceOptions opt;
  opt.width = 100, opt.height = 70;
  const GeneratedPiece piece = generatePiece(400, 21, opt);
  Model m(piece.workpiece, piece.deformation);
  OpGrid grid;
  grid.sync(m);
  std::mt19937 rng(5);
  PieceRandom prng(8);
  for (size_t k = 0; k < piece.operations.size(); ++k) {
    ASSERT_TRUE(m.add(piece.operations[k]).ok());
    EXPECT_EQ(grid.sync(m), 1u);  // only the new operation is inserted
    if (k % 40 == 39) {
      for (int u = 0; u < 6; ++u) m.undo();
      EXPECT_EQ(grid.sync(m), 0u);  // undo costs nothing
      checkAt(grid, m, rng);
      for (int u = 0; u < 2; ++u) m.redo();
      grid.sync(m);
      ASSERT_TRUE(m.add(randomTraceSegment(prng, piece)).ok());
      EXPECT_EQ(grid.sync(m), 1u);
      checkAt(grid, m, rng);
    }
  }
  checkAt(grid, m, rng);
}

// A grid of one kind (the renderer's of the patina strokes) lists those alone, and follows adds,
// undos, redos and a replaced redo tail as the whole grid does.
TEST(OpGrid, AFilteredGridListsItsKindAlone) {
  PieceOptions opt;
  opt.width = 100, opt.height = 70;
  const GeneratedPiece piece = generatePiece(300, 23, opt);
  Model m(piece.workpiece, piece.deformation);
  const OpGrid::Filter patina = [](const Operation& o) { return o.isPatina(); };
  OpGrid grid(0.0, patina);
  grid.sync(m);
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> ux(-45, 45), uy(-30, 30), ur(1.0, 6.0);
  auto stroke = [&] {
    Operation op;
    op.kind = OpKind::Patina;
    op.tinge = 1 + static_cast<int>(rng() % 4);
    op.a = ur(rng), op.strength = 0.7;
    Vec2 at{ux(rng), uy(rng)};
    for (int i = 0; i < 30; ++i) op.points.push_back(at), at.x += 0.8, at.y += 0.3 * std::sin(i * 0.4);
    return op;
  };
  int strokes = 0;
  for (size_t k = 0; k < piece.operations.size(); ++k) {
    ASSERT_TRUE(m.add(piece.operations[k]).ok());
    EXPECT_EQ(grid.sync(m), 0u);  // not one of its kind
    if (k % 30 == 29) {
      ASSERT_TRUE(m.add(stroke()).ok());
      EXPECT_EQ(grid.sync(m), 1u);
      ++strokes;
      for (int u = 0; u < 4; ++u) m.undo();
      grid.sync(m);
      checkAt(grid, m, rng, patina);
      m.redo();
      grid.sync(m);
      ASSERT_TRUE(m.add(stroke()).ok());  // the rest of the redo tail replaced
      EXPECT_EQ(grid.sync(m), 1u);
      checkAt(grid, m, rng, patina);
    }
  }
  ASSERT_GE(strokes, 9);
  checkAt(grid, m, rng, patina);
  // Some point lies under a stroke (the check above is not empty).
  std::vector<std::uint32_t> scratch;
  size_t listed = 0;
  for (int k = 0; k < 2000; ++k) listed += grid.at(ux(rng), uy(rng), scratch).size();
  EXPECT_GT(listed, 50u);
}

// A cleared model (a new sheet, a new visitor, the next attract piece) leaves the index as small
// as a new one: the cells' lists do not keep the storage the last piece needed.
TEST(OpGrid, AClearedModelGivesBackTheListsStorage) {
  PieceOptions opt;
  opt.width = 100, opt.height = 70;
  const GeneratedPiece piece = generatePiece(400, 22, opt);
  Model m(piece.workpiece, piece.deformation);
  OpGrid grid;
  grid.sync(m);
  const size_t empty = grid.memoryBytes();
  for (const Operation& op : piece.operations) ASSERT_TRUE(m.add(op).ok());
  grid.sync(m);
  ASSERT_GT(grid.memoryBytes(), empty + 100000);
  m.clear();
  EXPECT_EQ(grid.sync(m), 0u);
  EXPECT_LE(grid.memoryBytes(), empty);  // the id and support lists' storage too
  std::mt19937 rng(6);
  checkAt(grid, m, rng);
  // And it follows the next piece as before.
  for (size_t k = 0; k < 50; ++k) ASSERT_TRUE(m.add(piece.operations[k]).ok());
  EXPECT_EQ(grid.sync(m), 50u);
  checkAt(grid, m, rng);
}

}  // namespace
}  // namespace emboss
