// SetOpUpper: a set operation's upper bound over a box holds every value combine() takes in it,
// and so do its bound wherever the tool is and its raise, and it stays tight where set operations pile up (a bound that grew with
// |f| failed every interval test of a ray through a pile of flat punches, far above the sheet).
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <tuple>
#include <vector>

#include "render/set_op_bounds.h"

namespace emboss {
namespace {

Operation blend(OpKind kind, ToolShape::Type type, const Vec3& c) {
  Operation o;
  o.kind = kind;
  o.tool.type = type;
  o.tool.center = c;
  o.tool.r = 1.5;
  o.tool.end = {c.x + 2.0, c.y - 1.0, c.z + 0.5};
  o.tool.half = {3.0, 2.1, 1.0};
  o.a1 = 0.3, o.a2 = 1.2, o.a3 = 1.2;
  return o;
}

// The operations a test draws from: each kind on each tool shape, near the origin.
std::vector<PreparedOp> someOperations() {
  std::vector<PreparedOp> ops;
  for (OpKind k : {OpKind::BlendUnion, OpKind::BlendSubtract, OpKind::Subtract})
    for (ToolShape::Type t : {ToolShape::Type::Sphere, ToolShape::Type::Cylinder, ToolShape::Type::Flat})
      ops.emplace_back(blend(k, t, {0.3, -0.2, 0.1}));
  return ops;
}

// A box somewhere from inside the tools to well beyond their taper, of any size up to 2 mm, and
// random points in it.
struct RandomBox {
  double lo[3], hi[3];
  explicit RandomBox(std::mt19937& rng) {
    std::uniform_real_distribution<double> u(0.0, 1.0);
    for (int k = 0; k < 3; ++k) {
      lo[k] = -8.0 + 16.0 * u(rng);
      hi[k] = lo[k] + 2.0 * u(rng) * u(rng);
    }
  }
  P3<Interval> box() const { return {Interval(lo[0], hi[0]), Interval(lo[1], hi[1]), Interval(lo[2], hi[2])}; }
  P3<double> point(std::mt19937& rng) const {
    std::uniform_real_distribution<double> u(0.0, 1.0);
    return {lo[0] + (hi[0] - lo[0]) * u(rng), lo[1] + (hi[1] - lo[1]) * u(rng), lo[2] + (hi[2] - lo[2]) * u(rng)};
  }
};

// The upper ends alone (what proves f < 0): above every value combine() takes in the box for any
// f up to the given upper end; the bound without the tool's place is looser still, and infinite
// for a union; and f raised by the operation's raise() is above them all.
TEST(SetOpBounds, UpperEndsHoldEveryValueBelowThem) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const std::vector<PreparedOp> ops = someOperations();
  for (int trial = 0; trial < 3000; ++trial) {
    const PreparedOp& op = ops[static_cast<size_t>(trial) % ops.size()];
    const RandomBox rb(rng);
    const P3<Interval> box = rb.box();
    const double fHi = -30.0 * u(rng) * u(rng) + 2.0 * u(rng);
    const SetOpUpper bounds(op.op());
    const double upper = bounds.over(fHi, box), anywhere = bounds.anywhere(fHi);
    if (op.op().kind == OpKind::BlendUnion)
      EXPECT_TRUE(std::isinf(anywhere) && std::isinf(bounds.raise()));
    else
      ASSERT_GE(anywhere, upper - 1e-9) << "trial " << trial;
    for (int s = 0; s < 40; ++s) {
      const P3<double> p = rb.point(rng);
      // f anywhere below fHi, down to a pile's depths, and fHi itself.
      const double f = s == 0 ? fHi : fHi - 300.0 * u(rng) * u(rng) * u(rng);
      const double v = op.combine(f, p);
      ASSERT_LE(v, upper) << "trial " << trial << " f " << f;
      ASSERT_LE(v, anywhere) << "trial " << trial << " f " << f;
      // (The margin the walk's Lipschitz steps inside windows keep, kRaiseMargin, is 1e-6.)
      ASSERT_LE(v, f + bounds.raise() + 1e-9) << "trial " << trial << " f " << f;
    }
  }
}

// Twelve flat punches on a spot, then a bead: a cell 5 mm above them, where f is about -6 (the
// sheet), must be proven outside. Over a box each subtraction about doubles how negative f's lower
// end gets, and the earlier bound, with |f| in its upper end, gave +21 008 here.
TEST(SetOpBounds, StayBelowZeroAboveAPile) {
  std::vector<PreparedOp> pile;
  for (int i = 0; i < 12; ++i)
    pile.emplace_back(blend(OpKind::BlendSubtract, ToolShape::Type::Flat, {0.2 * i, -0.1 * i, 0.0}));
  pile.emplace_back(blend(OpKind::BlendUnion, ToolShape::Type::Sphere, {1.0, 0.0, -1.0}));
  // A cell of a ray 5 mm above the tools' tops, and f there (its upper end -5.9).
  const P3<Interval> box{Interval(0.9, 1.0), Interval(-0.3, -0.2), Interval(6.0, 6.3)};
  double exact = -6.0, hi = -5.9, anywhere = -5.9;
  for (const PreparedOp& op : pile) {
    exact = op.combine(exact, P3<double>{0.95, -0.25, 6.1});
    const SetOpUpper bounds(op.op());
    hi = bounds.over(hi, box);
    anywhere = op.op().kind == OpKind::BlendUnion ? bounds.over(anywhere, box) : bounds.anywhere(anywhere);
  }
  EXPECT_GE(hi, exact);
  EXPECT_LT(hi, -5.0);
  // Wherever the subtractions' tools are, their bumps raise f there by less than 1 in all.
  EXPECT_LT(anywhere, -4.9);
}

// A ball's smooth union far from its tool: at nearRadius or more from the centre, combine(f, p) < 0
// for every f below -raise (a few tool sizes of f, and far below); and the raise is nearly the
// least that holds: a tenth less, some f in between gives combine(f, p) >= 0 there (so a bound a
// tenth short fails). Balls of the kiosk's, the generator's and other sizes and blends.
TEST(SetOpBounds, ABallsUnionIsBelowZeroFarFromItWhereFIsBelowItsRaise) {
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  int balls = 0, tight = 0;
  for (const auto& [r, a1, a2, a3] : {std::tuple{2.0, 0.27, 1.0, 2.0}, {1.5, 0.4, 1.0, 3.0}, {0.6, 0.5, 0.8, 1.2},
                                      {3.0, 1.0, 2.0, 6.0}, {1.0, 0.0, 1.0, 1.0}, {0.3, 0.4, 1.0, 0.6}}) {
    Operation o = blend(OpKind::BlendUnion, ToolShape::Type::Sphere, {0.5, -0.7, 2.0});
    o.tool.r = r, o.a1 = a1, o.a2 = a2, o.a3 = a3;
    const PreparedOp op(o);
    const std::optional<BallFar> far = ballFarBound(o, 1e9);
    if (!far) continue;
    ++balls;
    EXPECT_GT(far->nearRadius, r);
    bool reached = false;
    for (int k = 0; k < 20000; ++k) {
      // A point at nearRadius to 3 of it from the centre, in any direction.
      const double dist = far->nearRadius * (1.0 + (k % 4 == 0 ? 0.0 : 2.0 * u(rng) * u(rng)));
      double v[3];
      double len = 0.0;
      do {
        for (double& c : v) c = 2.0 * u(rng) - 1.0;
        len = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
      } while (len < 1e-3);
      const P3<double> p{o.tool.center.x + dist * v[0] / len, o.tool.center.y + dist * v[1] / len,
                         o.tool.center.z + dist * v[2] / len};
      // f from just below -raise to far below it.
      const double f = -far->raise * (1.0 + 1e-9) - (k % 3 == 0 ? 0.0 : 20.0 * std::pow(u(rng), 3.0));
      ASSERT_LT(op.combine(f, p), 0.0) << "r " << r << ", a1 " << a1 << ": f " << f << " at " << dist << " from the centre";
      // Between a tenth below the raise and the raise, at nearRadius itself: somewhere >= 0.
      if (k % 4 == 0) {
        const double g = -far->raise * (0.9 + 0.1 * u(rng));
        reached |= op.combine(g, p) >= 0.0;
      }
    }
    tight += reached;
  }
  EXPECT_EQ(balls, 6) << "every ball here has a far bound";
  EXPECT_EQ(tight, 5) << "a tenth less than the raise fails for every ball with a bump (a1 > 0)";
}

}  // namespace
}  // namespace emboss
