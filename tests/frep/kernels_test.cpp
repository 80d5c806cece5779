// The paper's equations against values worked out by hand.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <memory>

#include "frep/kernels.h"
#include "frep/model.h"
#include "frep/workpieces.h"
#include "scene/scene.h"
#include "tools/tool_catalogue.h"

namespace emboss {
namespace {

constexpr double kTol = 1e-12;

Model plateModel(Deformation d, double w = 20, double h = 20, double t = 0.5) {
  return Model(std::make_shared<Plate>(w, h, t), d);
}

double at(const Model& m, double x, double y, double z) { return m.evaluate(P3<double>{x, y, z}); }

TEST(Equations, PlateIsEquation1) {
  Model m = plateModel(Deformation::Sheet, 10, 8, 0.5);
  // min(x + w, w - x, y + h, h - y, z + d, d - z) at (1, 2, 0.2) = min(11, 9, 10, 6, 0.7, 0.3).
  EXPECT_NEAR(at(m, 1, 2, 0.2), 0.3, kTol);
  EXPECT_NEAR(at(m, 9.5, 2, 0), 0.5, kTol);   // w - x = 0.5 is the least
  EXPECT_NEAR(at(m, 0, 0, 0.7), -0.2, kTol);  // outside, above the front face
}

TEST(Equations, TraceFromTheFrontIsEquation2) {
  for (Deformation def : {Deformation::Offset, Deformation::Sheet}) {
    Model m = plateModel(def);
    Operation op;
    op.kind = OpKind::Trace;
    op.side = Side::Front;
    op.a = 1.0;
    op.points = {{0, 0}, {10, 0}};
    ASSERT_TRUE(m.add(op));
    // Across the segment: t = 0.5, a^3 / (t^2 + a^2) = 1 / 1.25 = 0.8; plate value 0.3 at z = 0.2.
    EXPECT_NEAR(at(m, 5, 0.5, 0.2), 0.3 - 0.8, kTol) << deformationName(def);
    // Beyond the end point the same profile applies radially: distance 2 -> 1 / 5.
    EXPECT_NEAR(at(m, 12, 0, 0.2), 0.3 - 0.2, kTol);
  }
}

TEST(Equations, OffsetModelMirrorsTheBackFaceSheetModelDoesNot) {
  Operation op;
  op.kind = OpKind::Trace;
  op.side = Side::Front;
  op.a = 1.0;
  op.points = {{0, 0}, {10, 0}};
  Model offset = plateModel(Deformation::Offset), sheet = plateModel(Deformation::Sheet);
  ASSERT_TRUE(offset.add(op));
  ASSERT_TRUE(sheet.add(op));
  // On the line the offset is a = 1. Offset model: f = plate - 1; at z = -0.3 the plate gives 0.2,
  // so f = -0.8: the back face moved inward too (the paper's mirror effect, the sheet thinned).
  EXPECT_NEAR(at(offset, 5, 0, -0.3), 0.2 - 1.0, kTol);
  // Sheet model: both faces move down by 1: the front face is at z = -0.5, the back at z = -1.5.
  EXPECT_NEAR(at(sheet, 5, 0, -0.5), 0.0, kTol);
  EXPECT_NEAR(at(sheet, 5, 0, -1.5), 0.0, kTol);
  EXPECT_NEAR(at(sheet, 5, 0, -1.0), 0.5, kTol);  // mid-sheet: thickness kept, 2d = 1
}

TEST(Equations, TraceFromBehindRaises) {
  Model m = plateModel(Deformation::Offset);
  Operation op;
  op.kind = OpKind::Trace;
  op.side = Side::Back;
  op.a = 1.0;
  op.points = {{0, 0}, {10, 0}};
  ASSERT_TRUE(m.add(op));
  EXPECT_NEAR(at(m, 5, 0.5, 0.2), 0.3 + 0.8, kTol);
}

TEST(Equations, PunchIsEquation3) {
  Operation op;
  op.kind = OpKind::Punch;
  op.side = Side::Back;
  op.a = 2.0, op.p = 0.5, op.q = 1.5;
  op.at = {0, 0, 0.5};
  {
    // The paper's |P'| is a distance in space: at (1, 1, 1.5), |P'|^2 = 3, f_offset = 0.5 * 8 / (1.5 * 3 + 4).
    Model m = plateModel(Deformation::Offset);
    ASSERT_TRUE(m.add(op));
    EXPECT_NEAR(at(m, 1, 1, 1.5), std::min(1.5 + 0.5, 0.5 - 1.5) + 4.0 / 8.5, kTol);
  }
  {
    // The sheet measures it along the sheet: r^2 = 2, D = 4 / 7 moves both faces up.
    Model m = plateModel(Deformation::Sheet);
    ASSERT_TRUE(m.add(op));
    EXPECT_NEAR(at(m, 1, 1, 0.5 + 4.0 / 7.0), 0.0, kTol);
    EXPECT_NEAR(at(m, 1, 1, 4.0 / 7.0), 0.5, kTol);
  }
  // Lowering from the front: the same offset subtracted.
  op.side = Side::Front;
  Model m = plateModel(Deformation::Offset);
  ASSERT_TRUE(m.add(op));
  EXPECT_NEAR(at(m, 1, 1, 1.5), std::min(1.5 + 0.5, 0.5 - 1.5) - 4.0 / 8.5, kTol);
}

TEST(Equations, SupportIsExactWithinThreeLengthsThenTapersToZero) {
  Model m = plateModel(Deformation::Offset);
  Operation op;
  op.kind = OpKind::Trace;
  op.side = Side::Back;
  op.a = 1.0;
  op.points = {{0, 0}, {10, 0}};
  ASSERT_TRUE(m.add(op));
  const double base = 0.3;  // plate at z = 0.2
  EXPECT_NEAR(at(m, 5, 2.999, 0.2), base + 1.0 / (2.999 * 2.999 + 1.0), kTol);
  // At 3.5 a the smootherstep taper is one half: 1 / (3.5^2 + 1) * 0.5.
  EXPECT_NEAR(at(m, 5, 3.5, 0.2), base + 0.03773584905660377, kTol);
  EXPECT_EQ(at(m, 5, 4.0, 0.2), base);
  EXPECT_EQ(at(m, 5, 7.0, 0.2), base);
  // The support rectangle is the segment grown by 4 a.
  const Box2 s = m.operations()[0].support();
  EXPECT_DOUBLE_EQ(s.x0, -4.0);
  EXPECT_DOUBLE_EQ(s.x1, 14.0);
  EXPECT_DOUBLE_EQ(s.y1, 4.0);
}

TEST(Equations, PunchCharacteristicLengthIsAOverSqrtQ) {
  Operation op;
  op.kind = OpKind::Punch;
  op.a = 2.0, op.p = 1.0, op.q = 4.0;
  op.at = {3, 4, 0};
  EXPECT_DOUBLE_EQ(op.characteristicLength(), 1.0);
  PreparedOp prep(op);
  EXPECT_DOUBLE_EQ(prep.support().x0, -1.0);  // 3 - 4 * 1
  EXPECT_DOUBLE_EQ(prep.support().y1, 8.0);
  EXPECT_EQ(prep.offset(P3<double>{3 + 4.0, 4, 0}, Deformation::Sheet), 0.0);
  EXPECT_GT(prep.offset(P3<double>{3 + 3.9, 4, 0}, Deformation::Sheet), 0.0);
}

TEST(Equations, BlendingUnionAndSubtractionAreEquation4) {
  // f + g + sqrt(f^2 + g^2) + a1 / (1 + (f/a2)^2 + (g/a3)^2) at f = 0.3, g = 0.75, a = (1, 1, 1).
  EXPECT_NEAR(kernels::blendUnion(0.3, 0.75, 1.0, 1.0, 1.0), 2.462918442704064, kTol);
  // f - g - sqrt(f^2 + g^2) + a1 / (1 + (f/a2)^2 + (g/a3)^2) at a3 = 2.
  EXPECT_NEAR(kernels::blendSubtract(0.3, 0.75, 1.0, 1.0, 2.0), -0.4451794950671283, kTol);
  EXPECT_EQ(kernels::subtract(0.3, 0.75), -0.75);
  EXPECT_EQ(kernels::subtract(0.3, -0.75), 0.3);
}

TEST(Equations, BlendUnionOperationNearTheToolIsExact) {
  Model m = plateModel(Deformation::Offset);
  Operation op;
  op.kind = OpKind::BlendUnion;
  op.tool.type = ToolShape::Type::Sphere;
  op.tool.center = {0, 0, 0.5};
  op.tool.r = 1.0;
  op.a1 = 0.5, op.a2 = 1.0, op.a3 = 1.0;
  ASSERT_TRUE(m.add(op));
  const double x = 0.5, y = 0, z = 0.8;
  const double f = 0.5 - z;                                  // the plate's front face term
  const double g = 1.0 - (x * x + y * y + (z - 0.5) * (z - 0.5));  // r^2 - |P - c|^2
  EXPECT_NEAR(at(m, x, y, z), kernels::blendUnion(f, g, 0.5, 1.0, 1.0), kTol);
  // Far from the tool (beyond 4 r from its surface) the plate is untouched.
  EXPECT_EQ(at(m, 10, 0, 0.2), 0.3);
}

// A set operation's blend is whole within 3 tool sizes L of the tool, tapered to the untouched f
// from there to 4 L (one half of the blend's change at 3.5 L), and exactly f beyond: a flat tool
// 4 x 2 x 1 mm (L = 0.5 mm) beating the plate down, beside it at the height of its face.
TEST(Equations, ASetOperationTapersFromThreeToFourToolSizes) {
  Model m = plateModel(Deformation::Offset);
  Operation op;
  op.kind = OpKind::BlendSubtract;
  op.tool.type = ToolShape::Type::Flat;
  op.tool.center = {0, 0, 1.3};
  op.tool.half = {2, 1, 0.5};
  op.a1 = 0.135, op.a2 = 1.2, op.a3 = 1.2;
  ASSERT_TRUE(m.add(op));
  const double z = 0.8, f = 0.5 - z;  // the plate's front face term
  auto blended = [&](double s) { return kernels::blendSubtract(f, -0.5 * s, 0.135, 1.2, 1.2); };  // g = -s L
  EXPECT_NEAR(at(m, 2.0 + 0.5 * 2.9, 0, z), blended(2.9), kTol);
  EXPECT_NEAR(at(m, 2.0 + 0.5 * 3.5, 0, z), f + 0.5 * (blended(3.5) - f), kTol);
  EXPECT_NEAR(at(m, 2.0 + 0.5 * 3.1, 0, z), f + kernels::taper(3.1) * (blended(3.1) - f), kTol);
  EXPECT_EQ(at(m, 2.0 + 0.5 * 4.0, 0, z), f);
  EXPECT_EQ(at(m, 0.0, 1.0 + 0.5 * 4.5, z), f);
  EXPECT_NEAR(at(m, 0.0, 0.0, z), kernels::blendSubtract(f, 0.0, 0.135, 1.2, 1.2), kTol);  // on the tool's face
}

TEST(Equations, SubtractCutsThePlate) {
  Model m = plateModel(Deformation::Sheet);
  Operation op;
  op.kind = OpKind::Subtract;
  op.tool.type = ToolShape::Type::Cylinder;
  op.tool.center = {0, 0, -2};
  op.tool.end = {0, 0, 2};
  op.tool.r = 1.0;
  ASSERT_TRUE(m.add(op));
  EXPECT_LT(at(m, 0, 0, 0), 0.0);    // a hole through the sheet
  EXPECT_NEAR(at(m, 0.5, 0, 0), -(1.0 - 0.25), kTol);
  EXPECT_NEAR(at(m, 1.2, 0, 0), std::min(0.5, -(1.0 - 1.44)), kTol);
}

TEST(Equations, FlatToolIsARectangularFace) {
  ToolShape t;
  t.type = ToolShape::Type::Flat;
  t.center = {1, 2, 3};
  t.half = {2, 1, 0.5};
  EXPECT_NEAR(t.value(P3<double>{1, 2, 3}), 0.5, kTol);
  EXPECT_NEAR(t.value(P3<double>{2.5, 2, 3}), 0.5, kTol);  // min(0.5, 1, 0.5)
  EXPECT_NEAR(t.value(P3<double>{4, 2, 3}), -1.0, kTol);
}

TEST(Equations, RegionRaisesInsideAndDescendsOutside) {
  Model m = plateModel(Deformation::Offset);
  Operation op;
  op.kind = OpKind::Region;
  op.side = Side::Back;
  op.points = {{-5, -5}, {5, -5}, {5, 5}, {-5, 5}};
  op.height = 0.8;
  op.falloff = 2.0;
  ASSERT_TRUE(m.add(op));
  EXPECT_NEAR(at(m, 0, 0, 0.2), 0.3 + 0.8, kTol);  // uniform inside
  EXPECT_NEAR(at(m, 4.9, 4.9, 0.2), 0.3 + 0.8, kTol);
  // Outside, by distance t to the contour: height * L^2 / (t^2 + L^2); t = 1 -> 0.8 * 4 / 5.
  EXPECT_NEAR(at(m, 6, 0, 0.2), 0.3 + 0.64, kTol);
  EXPECT_EQ(at(m, 14, 0, 0.2), 0.3);  // beyond 4 L
}

TEST(Equations, RegionUsesOddParityForConcaveContours) {
  // A "U": the notch between the arms is outside.
  Model m = plateModel(Deformation::Offset);
  Operation op;
  op.kind = OpKind::Region;
  op.points = {{-6, -6}, {6, -6}, {6, 6}, {2, 6}, {2, -2}, {-2, -2}, {-2, 6}, {-6, 6}};
  op.height = 1.0;
  op.falloff = 0.5;
  ASSERT_TRUE(m.add(op));
  EXPECT_NEAR(at(m, -4, 4, 0.2), 1.3, kTol);
  EXPECT_NEAR(at(m, 0, 4, 0.2), 0.3, kTol);  // 2 from every edge: beyond 4 L = 2
}

TEST(Equations, PressPlacesPunchesAlongThePath) {
  Operation op;
  op.kind = OpKind::Press;
  op.a = 1.0, op.p = 0.2, op.q = 1.0;
  op.points = {{0, 0}, {20, 0}};
  PreparedOp prep(op);
  // Every L / 4 = 0.25 mm, end points included.
  ASSERT_EQ(prep.pressPoints().size(), 81u);
  EXPECT_DOUBLE_EQ(prep.pressPoints().back().x, 20.0);
  // Smooth: along the middle of the path the ridge height varies by less than 5e-5 of itself.
  // (from x = 8 to 12 every point within reach, 4 L, lies on the path).
  const double h0 = prep.offset(P3<double>{10.0, 0, 0}, Deformation::Sheet);
  for (double x = 8.0; x <= 12.0; x += 0.05)
    EXPECT_NEAR(prep.offset(P3<double>{x, 0, 0}, Deformation::Sheet), h0, 5e-5 * h0);
}

// A stroke split into pieces (as a tracer's stroke is, every kTraceSegment mm): joined, the pieces
// sum to the whole line's profile; unjoined, each joint is a bead of twice the depth.
TEST(Equations, JoinedTracePiecesSumToTheWholeLine) {
  Operation whole;
  whole.kind = OpKind::Trace;
  whole.side = Side::Front;
  whole.a = 0.6;
  for (int i = 0; i <= 24; ++i) whole.points.push_back({-12.0 + i, 0.0});
  const PreparedOp one(whole);
  std::vector<Operation> pieces;
  for (int k = 0; k < 6; ++k) {
    Operation piece = whole;
    piece.points.assign(whole.points.begin() + 4 * k, whole.points.begin() + 4 * k + 5);
    pieces.push_back(piece);
  }
  std::vector<PreparedOp> loose(pieces.begin(), pieces.end());
  joinTracePieces(pieces);
  ASSERT_TRUE(pieces[0].joinEnd.on());
  ASSERT_FALSE(pieces[0].joinStart.on());
  EXPECT_EQ(pieces[2].joinStart.r, pieces[1].joinEnd.r);
  EXPECT_DOUBLE_EQ(pieces[1].joinEnd.r, 0.9);  // 1.5 a
  std::vector<PreparedOp> joined(pieces.begin(), pieces.end());
  double worstJoined = 0, worstLoose = 0;
  for (double x = -14; x <= 14; x += 0.05)
    for (double y = -2.5; y <= 2.5; y += 0.1) {
      const P3<double> p{x, y, 0.0};
      const double ref = one.offset(p, Deformation::Sheet);
      double sj = 0, sl = 0;
      for (const auto& o : joined) sj += o.offset(p, Deformation::Sheet);
      for (const auto& o : loose) sl += o.offset(p, Deformation::Sheet);
      worstJoined = std::max(worstJoined, std::abs(sj - ref));
      worstLoose = std::max(worstLoose, std::abs(sl - ref));
    }
  EXPECT_LT(worstJoined, 1e-12);
  EXPECT_NEAR(worstLoose, 0.6, 0.01);  // the bead: a second profile's peak a at each joint

  // A bend and a change of pressure at a joint: no bead, no dimple, no step along the line.
  Operation a = whole, b = whole;
  a.points = {{-6, 0}, {0, 0}};
  b.points = {{0, 0}, {4, 3}};
  b.a = 0.5;
  std::vector<Operation> bent{a, b};
  joinTracePieces(bent);
  const PreparedOp pa(bent[0]), pb(bent[1]);
  auto along = [&](double t) {  // the line itself, parametrised across the joint
    const P3<double> p = t < 0 ? P3<double>{t, 0.0, 0.0} : P3<double>{0.8 * t, 0.6 * t, 0.0};
    return -(pa.offset(p, Deformation::Sheet) + pb.offset(p, Deformation::Sheet));
  };
  double prev = along(-3.0);
  for (double t = -3.0; t <= 3.0; t += 0.01) {
    const double v = along(t);
    // Between the two depths (with the joint along the piece before alone, there was a dip of 1 %
    // just after the 37-degree bend, to 0.4948; with the bisector, none: 0.5000).
    EXPECT_GE(v, 0.999 * 0.5) << t;
    EXPECT_LE(v, 0.6 + 1e-9) << t;
    EXPECT_LT(std::abs(v - prev), 0.01) << t;
    prev = v;
  }
}

// A bend where one piece hands over to the next (a corner of a traced frame, a star's point): the
// two pieces add up to the profile of the whole bent line, a single trace, near the corner and
// past it. (The joint's direction was the piece before's alone: along a piece leaving at a right
// angle the hand-over weight then ran across the groove for that piece's whole length, and the
// groove was half as deep on its line.)
TEST(Equations, PiecesJoinedAtABendAddUpToTheBentLine) {
  for (const double bendDeg : {20.0, 37.0, 60.0, 90.0, 120.0, 150.0}) {
    const double t = bendDeg * std::numbers::pi / 180.0;
    const Vec2 out{6.0 * std::cos(t), 6.0 * std::sin(t)};  // the second piece's end
    Operation whole;
    whole.kind = OpKind::Trace;
    whole.side = Side::Front;
    whole.a = 0.6;
    whole.points = {{-6, 0}, {0, 0}, out};
    Operation a = whole, b = whole;
    a.points = {{-6, 0}, {0, 0}};
    b.points = {{0, 0}, out};
    std::vector<Operation> ops{a, b};
    joinTracePieces(ops);
    ASSERT_TRUE(ops[0].joinEnd.on() && ops[1].joinStart.on());
    const PreparedOp one(whole), pa(ops[0]), pb(ops[1]);
    double nearCorner = 0, past = 0;
    for (double x = -5; x <= 5; x += 0.05)
      for (double y = -5; y <= 5; y += 0.05) {
        const P3<double> p{x, y, 0.0};
        const double err = std::abs(pa.offset(p, Deformation::Sheet) + pb.offset(p, Deformation::Sheet) - one.offset(p, Deformation::Sheet));
        (std::hypot(x, y) < 2.0 ? nearCorner : past) = std::max(std::hypot(x, y) < 2.0 ? nearCorner : past, err);
      }
    // Measured, in units of the depth a: 0.013 (20 degrees) to 0.066 (90) within 2 mm of the
    // corner, 0.006 to 0.030 past it. The joint along the piece before alone: 0.58 and 0.64 at a
    // right angle, 1.0 beyond; the bisector with the half width unscaled: 0.118 and 0.111 at 150
    // degrees (a hairpin's arms then shared the hand-over for 3.5 mm).
    EXPECT_LT(nearCorner, 0.08 * whole.a) << bendDeg << " deg";
    EXPECT_LT(past, 0.035 * whole.a) << bendDeg << " deg";
    std::printf("bend %5.1f deg: worst %.4f a near the corner, %.4f a past it\n", bendDeg, nearCorner / whole.a, past / whole.a);
  }
}

// A closed line (a circle traced in pieces, as a piece's contours are): joined where it closes as
// well, its groove is as deep there as anywhere along it; a line that stops short of its start is
// left open, and closed without the joint the circle had a bead of twice the depth there.
TEST(Equations, AClosedLineHasNoBeadWhereItCloses) {
  const double radius = 5.0, a = 0.6;
  std::vector<Vec2> circle;
  for (int k = 0; k <= 64; ++k) {
    const double t = 2.0 * std::numbers::pi * k / 64;
    circle.push_back({radius * std::cos(t), radius * std::sin(t)});
  }
  ASSERT_NE(circle.back().y, circle.front().y);  // closed only to rounding: 2 pi is not exact
  auto piecesOf = [&](const std::vector<Vec2>& line) {
    std::vector<Operation> pieces;
    for (size_t k = 0; k + 1 < line.size(); k += 8) {
      Operation piece;
      piece.kind = OpKind::Trace;
      piece.side = Side::Front;
      piece.a = a;
      piece.points.assign(line.begin() + static_cast<std::ptrdiff_t>(k), line.begin() + static_cast<std::ptrdiff_t>(std::min(k + 9, line.size())));
      pieces.push_back(piece);
    }
    return pieces;
  };
  auto depthAlong = [](const std::vector<Operation>& pieces, double angle) {
    const std::vector<PreparedOp> prepared(pieces.begin(), pieces.end());
    const P3<double> p{5.0 * std::cos(angle), 5.0 * std::sin(angle), 0.0};
    double d = 0;
    for (const auto& o : prepared) d -= o.offset(p, Deformation::Sheet);
    return d;
  };

  std::vector<Operation> closed = piecesOf(circle);
  ASSERT_EQ(closed.size(), 8u);
  std::vector<Operation> loose = closed;
  joinTracePieces(closed);
  ASSERT_TRUE(closed.front().joinStart.on());
  ASSERT_TRUE(closed.back().joinEnd.on());
  EXPECT_EQ(closed.back().points.back().x, closed.front().points.front().x);  // one joint point
  EXPECT_EQ(closed.back().points.back().y, closed.front().points.front().y);
  EXPECT_EQ(closed.front().joinStart.r, closed.back().joinEnd.r);
  const double middle = depthAlong(closed, std::numbers::pi);  // half way round, away from the closing
  for (double t = -0.3; t <= 0.3; t += 0.005) EXPECT_NEAR(depthAlong(closed, t), middle, 0.01 * middle) << t;
  EXPECT_GT(depthAlong(loose, 0.0), 1.9 * middle);  // unjoined there: the bead

  std::vector<Vec2> open = circle;
  open.back() = {open.back().x, open.back().y - 1e-3};  // stops a micrometre short
  std::vector<Operation> gap = piecesOf(open);
  joinTracePieces(gap);
  EXPECT_FALSE(gap.front().joinStart.on());
  EXPECT_FALSE(gap.back().joinEnd.on());
  EXPECT_TRUE(gap.front().joinEnd.on());

  // One piece that closes on itself is not joined to itself.
  std::vector<Operation> ring = {closed.front()};
  ring[0].points = circle;
  ring[0].joinStart = ring[0].joinEnd = TraceJoin{};
  joinTracePieces(ring);
  EXPECT_FALSE(ring[0].joinStart.on());
}

TEST(Equations, InvalidParametersAreRefused) {
  Model m = plateModel(Deformation::Sheet);
  Operation op;
  op.kind = OpKind::Punch;
  op.a = -1;
  const Status s = m.add(op);
  ASSERT_FALSE(s);
  EXPECT_NE(s.error().find("a: -1 is out of range"), std::string::npos) << s.error();
  EXPECT_EQ(m.activeCount(), 0u);
}

}  // namespace
}  // namespace emboss
