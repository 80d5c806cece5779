// The model: undo and redo, gradients, interval bounds, and the index against the naive evaluation.
#include <gtest/gtest.h>

#include <cstring>
#include <memory>
#include <random>

#include "frep/model.h"
#include "frep/op_grid.h"
#include "frep/workpieces.h"

namespace emboss {
namespace {

// A small random relief: traces, punches from both sides, a press, a region and set operations.
std::vector<Operation> randomOps(unsigned seed, int n, double extent) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> pos(-extent, extent), unit(0.0, 1.0);
  std::vector<Operation> ops;
  for (int i = 0; i < n; ++i) {
    Operation op;
    const int kind = static_cast<int>(unit(rng) * 7);
    op.side = unit(rng) < 0.5 ? Side::Front : Side::Back;
    switch (kind) {
      case 0:
      case 1: {
        op.kind = OpKind::Trace;
        op.a = 0.3 + unit(rng);
        Vec2 p{pos(rng), pos(rng)};
        for (int k = 0; k < 3; ++k) {
          op.points.push_back(p);
          p.x += 3 * (unit(rng) - 0.5), p.y += 3 * (unit(rng) - 0.5);
        }
        // Half of them joined to a (notional) piece before or after.
        for (TraceJoin* j : {&op.joinStart, &op.joinEnd}) {
          if (unit(rng) < 0.5) continue;
          const double angle = 6.283185307179586 * unit(rng);
          j->dir = {std::cos(angle), std::sin(angle)};
          j->r = 0.2 + unit(rng);
        }
        break;
      }
      case 2:
      case 3:
        op.kind = OpKind::Punch;
        op.a = 0.5 + 2 * unit(rng), op.p = 0.1 + 0.4 * unit(rng), op.q = 0.5 + unit(rng);
        op.at = {pos(rng), pos(rng), 0.5};
        break;
      case 4:
        op.kind = OpKind::Press;
        op.a = 0.5 + unit(rng), op.p = 0.05, op.q = 1;
        op.points = {{pos(rng), pos(rng)}, {pos(rng), pos(rng)}};
        break;
      case 5: {
        op.kind = OpKind::Region;
        const double cx = pos(rng), cy = pos(rng);
        op.points = {{cx - 3, cy - 2}, {cx + 3, cy - 2}, {cx + 1, cy + 3}, {cx - 2, cy + 1}};
        op.height = 0.5, op.falloff = 1.0;
        break;
      }
      default:
        op.kind = unit(rng) < 0.5 ? OpKind::BlendUnion : (unit(rng) < 0.5 ? OpKind::Subtract : OpKind::BlendSubtract);
        op.tool.type = unit(rng) < 0.6 ? ToolShape::Type::Sphere : ToolShape::Type::Flat;
        op.tool.center = {pos(rng), pos(rng), 0.5};
        op.tool.r = 1 + unit(rng);
        op.tool.half = {1, 0.7, 0.4};
        op.a1 = 0.3, op.a2 = 0.5, op.a3 = 1.0;
        break;
    }
    ops.push_back(op);
  }
  return ops;
}

TEST(Model, UndoRedoIsMultilevel) {
  Model m(std::make_shared<Plate>(20, 20, 0.5), Deformation::Sheet);
  const auto ops = randomOps(1, 6, 10);
  std::vector<double> values;
  const P3<double> probe{1.0, 2.0, 0.4};
  values.push_back(m.evaluate(probe));
  for (const auto& op : ops) {
    ASSERT_TRUE(m.add(op));
    values.push_back(m.evaluate(probe));
  }
  // Undo all the way back, checking each level, then redo all the way forward.
  for (int i = 6; i > 0; --i) {
    EXPECT_EQ(m.evaluate(probe), values[i]);
    ASSERT_TRUE(m.undo());
  }
  EXPECT_EQ(m.evaluate(probe), values[0]);
  EXPECT_FALSE(m.undo());
  for (int i = 1; i <= 6; ++i) {
    ASSERT_TRUE(m.redo());
    EXPECT_EQ(m.evaluate(probe), values[i]);
  }
  EXPECT_FALSE(m.redo());
  // An add after undo drops the redo tail.
  m.undo(), m.undo();
  ASSERT_TRUE(m.add(ops[0]));
  EXPECT_EQ(m.activeCount(), 5u);
  EXPECT_FALSE(m.canRedo());
  EXPECT_EQ(m.operations().size(), 5u);
}

TEST(Model, GradientMatchesCentralDifferences) {
  for (Deformation def : {Deformation::Sheet, Deformation::Offset}) {
    Model m(std::make_shared<Disc>(15, 0.5), def);
    for (const auto& op : randomOps(7, 30, 8)) ASSERT_TRUE(m.add(op));
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> pos(-9, 9), zpos(-1.5, 1.5);
    int checked = 0;
    for (int i = 0; i < 400; ++i) {
      const double x = pos(rng), y = pos(rng), z = zpos(rng);
      const Grad g = m.evaluate(P3<Grad>{Grad(x, 1, 0, 0), Grad(y, 0, 1, 0), Grad(z, 0, 0, 1)});
      const double h = 1e-6;
      auto f = [&](double a, double b, double c) { return m.evaluate(P3<double>{a, b, c}); };
      const double dx = (f(x + h, y, z) - f(x - h, y, z)) / (2 * h);
      const double dy = (f(x, y + h, z) - f(x, y - h, z)) / (2 * h);
      const double dz = (f(x, y, z + h) - f(x, y, z - h)) / (2 * h);
      // Skip the creases of min/max/abs, where the derivative jumps.
      const double fd = std::abs(dx - g.dx) + std::abs(dy - g.dy) + std::abs(dz - g.dz);
      if (fd > 1e-3) {
        const double d2 = std::abs(f(x + 2 * h, y, z) - 2 * f(x, y, z) + f(x - 2 * h, y, z));
        if (d2 > 1e-9) continue;
      }
      EXPECT_NEAR(g.dx, dx, 1e-4);
      EXPECT_NEAR(g.dy, dy, 1e-4);
      EXPECT_NEAR(g.dz, dz, 1e-4);
      EXPECT_EQ(g.v, f(x, y, z));
      ++checked;
    }
    EXPECT_GT(checked, 300);
  }
}

TEST(Model, IntervalBoundsContainEverySample) {
  for (Deformation def : {Deformation::Sheet, Deformation::Offset}) {
    Model m(std::make_shared<Bowl>(15, 3, 0.5), def);
    for (const auto& op : randomOps(11, 40, 8)) ASSERT_TRUE(m.add(op));
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> pos(-10, 10), zpos(-2, 4), size(0.01, 3), unit(0, 1);
    for (int i = 0; i < 300; ++i) {
      const double x0 = pos(rng), y0 = pos(rng), z0 = zpos(rng);
      const double sx = size(rng), sy = size(rng), sz = size(rng);
      const Interval b = m.evaluate(P3<Interval>{Interval(x0, x0 + sx), Interval(y0, y0 + sy), Interval(z0, z0 + sz)});
      for (int k = 0; k < 20; ++k) {
        const double v = m.evaluate(P3<double>{x0 + sx * unit(rng), y0 + sy * unit(rng), z0 + sz * unit(rng)});
        EXPECT_LE(b.lo, v + 1e-9);
        EXPECT_GE(b.hi, v - 1e-9);
      }
    }
  }
}

// A 40 x 30 mm plate under 300 random operations (randomOps(seed)).
Model denseRelief(Deformation def, unsigned seed) {
  Model m(std::make_shared<Plate>(40, 30, 0.5), def);
  for (const auto& op : randomOps(seed, 300, 35)) EXPECT_TRUE(m.add(op));
  return m;
}

TEST(Model, IndexedEvaluationEqualsNaiveBitForBit) {
  for (Deformation def : {Deformation::Sheet, Deformation::Offset}) {
    Model m = denseRelief(def, 21);
    OpGrid grid;
    grid.sync(m);
    std::mt19937 rng(9);
    std::uniform_real_distribution<double> px(-45, 45), py(-35, 35), pz(-3, 3);
    std::vector<std::uint32_t> scratch;
    for (int i = 0; i < 3000; ++i) {
      const P3<double> p{px(rng), py(rng), pz(rng)};
      EXPECT_EQ(m.evaluate(p, grid.at(p.x, p.y, scratch)), m.evaluate(p));
    }
    // And after undo, redo and an add that replaces the redo tail (incremental sync).
    m.undo(), m.undo(), m.undo();
    grid.sync(m);
    for (int i = 0; i < 500; ++i) {
      const P3<double> p{px(rng), py(rng), pz(rng)};
      EXPECT_EQ(m.evaluate(p, grid.at(p.x, p.y, scratch)), m.evaluate(p));
    }
    ASSERT_TRUE(m.add(randomOps(99, 1, 35)[0]));
    EXPECT_EQ(grid.sync(m), 1u);
    for (int i = 0; i < 500; ++i) {
      const P3<double> p{px(rng), py(rng), pz(rng)};
      EXPECT_EQ(m.evaluate(p, grid.at(p.x, p.y, scratch)), m.evaluate(p));
    }
  }
}

// A vertical line's values (the offsets under it summed once) are evaluate()'s bits at every z,
// in both deformation models, for points and for intervals along z: over a dense relief, with
// the line's candidates those of its column, and with every active operation.
TEST(Model, AVerticalLineGivesEvaluatesBitsAtEveryHeight) {
  for (Deformation def : {Deformation::Sheet, Deformation::Offset}) {
    const Model m = denseRelief(def, 23);
    OpGrid grid;
    grid.sync(m);
    std::vector<std::uint32_t> all(m.activeCount()), scratch;
    for (size_t i = 0; i < all.size(); ++i) all[i] = static_cast<std::uint32_t>(i);
    std::mt19937 rng(17);
    std::uniform_real_distribution<double> px(-45, 45), py(-35, 35), pz(-4, 4), dz(0.0, 0.5);
    int sets = 0;
    for (int i = 0; i < 200; ++i) {
      const double x = px(rng), y = py(rng);
      const std::span<const std::uint32_t> cell = grid.at(x, y, scratch);
      const std::vector<std::uint32_t> near(cell.begin(), cell.end());
      for (const auto& list : {std::span<const std::uint32_t>(near), std::span<const std::uint32_t>(all)}) {
        const Model::Line<double> line(m, x, y, list);
        const Model::Line<Interval> box(m, Interval(x), Interval(y), list);
        for (int k = 0; k < 20; ++k) {
          const double z = pz(rng), w = dz(rng);
          const double a = line(z), b = m.evaluate(P3<double>{x, y, z}, list);
          ASSERT_EQ(std::memcmp(&a, &b, sizeof a), 0) << "at " << x << ", " << y << ", " << z;
          const Interval c = box(Interval(z, z + w)), d = m.evaluate(P3<Interval>{Interval(x), Interval(y), Interval(z, z + w)}, list);
          ASSERT_EQ(std::memcmp(&c.lo, &d.lo, sizeof c.lo), 0) << "at " << x << ", " << y << ", " << z;
          ASSERT_EQ(std::memcmp(&c.hi, &d.hi, sizeof c.hi), 0) << "at " << x << ", " << y << ", " << z;
        }
      }
      for (std::uint32_t k : near) sets += m.operations()[k].op().isSet() && m.operations()[k].support().overlaps(Box2{x, y, x, y});
    }
    EXPECT_GT(sets, 25) << "lines through set operations";
  }
}

TEST(Model, BatchesEqualSinglePoints) {
  Model m(std::make_shared<Plate>(20, 20, 0.5), Deformation::Sheet);
  for (const auto& op : randomOps(4, 20, 10)) ASSERT_TRUE(m.add(op));
  std::vector<P3<double>> pts;
  for (int i = 0; i < 64; ++i) pts.push_back({i * 0.3 - 9, i * 0.2 - 6, 0.01 * i - 0.3});
  std::vector<double> v(pts.size());
  std::vector<Grad> g(pts.size());
  m.evaluate(pts, v);
  m.evaluateGradient(pts, g);
  for (size_t i = 0; i < pts.size(); ++i) {
    EXPECT_EQ(v[i], m.evaluate(pts[i]));
    EXPECT_EQ(g[i].v, v[i]);
  }
}

TEST(Model, SheetKeepsItsThickness) {
  // Under a punch from behind, both faces rise together: along the vertical through the punch the
  // sheet is inside for exactly 2 d.
  Model m(std::make_shared<Plate>(20, 20, 0.5), Deformation::Sheet);
  Operation op;
  op.kind = OpKind::Punch;
  op.a = 3, op.p = 0.5, op.q = 1, op.at = {0, 0, 0.5};
  ASSERT_TRUE(m.add(op));
  for (double x : {0.0, 1.0, 2.5, 5.0}) {
    int inside = 0;
    const int n = 40000;
    for (int i = 0; i < n; ++i)
      if (m.evaluate(P3<double>{x, 0, -2.0 + 6.0 * (i + 0.5) / n}) >= 0) ++inside;
    EXPECT_NEAR(inside * 6.0 / n, 1.0, 2e-3) << "at x = " << x;
  }
}

TEST(Model, BoundsHoldTheSurface) {
  Model m(std::make_shared<Plate>(20, 20, 0.5), Deformation::Offset);
  for (const auto& op : randomOps(8, 60, 15)) ASSERT_TRUE(m.add(op));
  const Box3 b = m.bounds();
  std::mt19937 rng(2);
  std::uniform_real_distribution<double> u(0, 1);
  for (int i = 0; i < 2000; ++i) {
    // Points just outside the bounds' faces are outside the model.
    const double x = b.x0 + (b.x1 - b.x0) * u(rng), y = b.y0 + (b.y1 - b.y0) * u(rng);
    EXPECT_LT(m.evaluate(P3<double>{x, y, b.z1 + 0.01}), 0.0);
    EXPECT_LT(m.evaluate(P3<double>{x, y, b.z0 - 0.01}), 0.0);
  }
}

}  // namespace
}  // namespace emboss
