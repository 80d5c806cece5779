// VmProgram::specialised: a program pruned to a box computes, at every point of the box, exactly
// the value of the whole program, with fewer instructions where one operand of a min or max wins.
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <random>
#include <string>

#include "frep/vm_generate.h"
#include "frep/vm_model.h"
#include "test_support.h"

namespace emboss {
namespace {

bool sameBits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

// Random boxes of sizes from a hundredth to the whole of [-r, r]^2 (z in [-r, r] for 3D models),
// random points in them (corners and edges included): the specialised program's value is the
// whole program's, bit for bit, and so are its gradient and its interval over the box's corner
// points. Returns the mean instructions of the specialised programs.
double checkSpecialisations(const VmProgram& p, double r, unsigned seed, int boxes) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  double sum = 0;
  for (int b = 0; b < boxes; ++b) {
    const double w = r * std::pow(10.0, -2.0 * u(rng));  // 0.01 r to r
    const double x0 = -r + (2 * r - w) * u(rng), y0 = -r + (2 * r - w) * u(rng), z0 = -r + (2 * r - w) * u(rng);
    const Interval X(x0, x0 + w), Y(y0, y0 + w), Z = p.usesZ() ? Interval(z0, z0 + w) : Interval(0.0);
    Interval whole;
    const VmProgram t = p.specialised(X, Y, Z, &whole);
    EXPECT_LE(t.size(), p.size());
    sum += static_cast<double>(t.size());
    const Interval direct = p.eval(X, Y, Z);
    EXPECT_TRUE(sameBits(whole.lo, direct.lo) && sameBits(whole.hi, direct.hi)) << "the interval over the box";
    for (int k = 0; k < 40; ++k) {
      auto pick = [&](const Interval& i) {
        const double v = u(rng);
        return v < 0.1 ? i.lo : v > 0.9 ? i.hi : i.lo + (i.hi - i.lo) * u(rng);
      };
      const double x = pick(X), y = pick(Y), z = pick(Z);
      const double a = p.eval(x, y, z), c = t.eval(x, y, z);
      EXPECT_TRUE(sameBits(a, c)) << "box " << b << " at " << x << " " << y << " " << z << ": " << a << " vs " << c;
      const Grad ga = p.eval(Grad(x, 1, 0, 0), Grad(y, 0, 1, 0), Grad(z, 0, 0, 1));
      const Grad gc = t.eval(Grad(x, 1, 0, 0), Grad(y, 0, 1, 0), Grad(z, 0, 0, 1));
      EXPECT_TRUE(sameBits(ga.v, gc.v) && sameBits(ga.dx, gc.dx) && sameBits(ga.dy, gc.dy) && sameBits(ga.dz, gc.dz));
    }
  }
  return sum / boxes;
}

TEST(VmPrune, SpecialisedProgramsComputeTheWholeProgramsValuesInTheirBox) {
  for (unsigned seed : {3u, 7u, 11u}) {
    SCOPED_TRACE("generated medallion, seed " + std::to_string(seed));
    auto p = VmProgram::parse(generateVmRelief(1500, seed), "generated");
    ASSERT_TRUE(p.ok()) << p.error();
    const double mean = checkSpecialisations(*p, 1.0, seed, 60);
    // A medallion is a union of primitives: a small box sees a few of them.
    EXPECT_LT(mean, 0.6 * static_cast<double>(p->size())) << "mean " << mean << " of " << p->size();
  }
}

TEST(VmPrune, FixtureModelsSpecialiseToTheirOwnValues) {
  EMBOSS_REQUIRE_FIXTURES(fixtures);
  int n = 0;
  for (const auto& e : std::filesystem::directory_iterator(fixtures / "vm")) {
    if (e.path().extension() != ".vm") continue;
    SCOPED_TRACE(e.path().filename().string());
    auto p = VmProgram::load(e.path());
    ASSERT_TRUE(p.ok()) << p.error();
    checkSpecialisations(*p, 1.5, 5, 40);
    ++n;
  }
  EXPECT_GT(n, 0) << "no .vm models in the fixtures";
}

TEST(VmPrune, AMinDecidedOverTheBoxKeepsOnlyItsWinner) {
  // min(x, y + 10) over x in [0, 1]: x wins everywhere, y is dropped.
  auto p = VmProgram::parse("a var-x\nb var-y\nc const 10\nd add b c\ne min a d\n", "t");
  ASSERT_TRUE(p.ok()) << p.error();
  const VmProgram t = p->specialised(Interval(0, 1), Interval(0, 1), Interval(0.0));
  EXPECT_EQ(t.size(), 1u);
  EXPECT_EQ(t.eval(0.25, 0.5, 0.0), 0.25);
  // Where the operands overlap nothing is decided.
  const VmProgram u = p->specialised(Interval(0, 20), Interval(0, 1), Interval(0.0));
  EXPECT_EQ(u.size(), p->size());
  // Operands closer than the intervals' rounding margin decide nothing either.
  auto q = VmProgram::parse("a var-x\nb const 1e-15\nc add a b\nd min a c\n", "t");
  ASSERT_TRUE(q.ok());
  EXPECT_EQ(q->specialised(Interval(0, 1), Interval(0.0), Interval(0.0)).size(), q->size());
}

TEST(VmPrune, ADecidedSmoothUnionLeavesNoArithmeticOnZeros) {
  // min(a, b) - max(k - |a - b|, 0)^2 / (4k) with a = x, b = y + 10 over [0, 1]^2: the min and
  // the max are decided, what is left computes m - 0^2 * c, folded to a alone.
  auto p = VmProgram::parse("a var-x\nv var-y\nt const 10\nb add v t\nd sub a b\nad abs d\nk const 0.05\n"
                            "kd sub k ad\nz const 0\nh max kd z\nh2 square h\nc const 5\ncorr mul h2 c\n"
                            "m min a b\nr sub m corr\n",
                            "t");
  ASSERT_TRUE(p.ok()) << p.error();
  const VmProgram t = p->specialised(Interval(0, 1), Interval(0, 1), Interval(0.0));
  EXPECT_EQ(t.size(), 1u);
  for (double x : {0.0, 0.3, 1.0, -0.0})
    for (double y : {0.0, 0.7})
      EXPECT_TRUE(sameBits(t.eval(x, y, 0.0), p->eval(x, y, 0.0))) << x << " " << y;
  // Where the blend acts nothing folds but the constants' own arithmetic.
  const VmProgram u = p->specialised(Interval(9.99, 10.01), Interval(0, 0.001), Interval(0.0));
  EXPECT_GT(u.size(), 10u);
  // x - (-0) is not x for x = -0 (it is +0): it stays.
  auto q = VmProgram::parse("a var-x\nz const -0\nr sub a z\n", "t");
  ASSERT_TRUE(q.ok()) << q.error();
  EXPECT_EQ(q->specialised(Interval(-1, 1), Interval(0.0), Interval(0.0)).size(), 3u);
  // An operation whose interval on a point may differ from the double's is not folded: sin(min(x,
  // 5)) over x >= 10 is sin(5), computed as the whole program computes it.
  auto s = VmProgram::parse("a var-x\nc const 5\nm min a c\nsc sin m\nr add a sc\n", "t");
  ASSERT_TRUE(s.ok()) << s.error();
  const VmProgram st = s->specialised(Interval(10, 11), Interval(0.0), Interval(0.0));
  EXPECT_EQ(st.size(), 4u);
  EXPECT_TRUE(sameBits(st.eval(Interval(10.5), Interval(0.0), Interval(0.0)).lo,
                       s->eval(Interval(10.5), Interval(0.0), Interval(0.0)).lo));
}

TEST(VmPrune, NonFiniteBoundsDecideNothing) {
  // 1/x over a box holding 0: the interval is the whole line, the min stays.
  auto p = VmProgram::parse("a var-x\nb recip a\nc const 5\nd min b c\n", "t");
  ASSERT_TRUE(p.ok()) << p.error();
  const VmProgram t = p->specialised(Interval(-1, 1), Interval(0.0), Interval(0.0));
  EXPECT_EQ(t.size(), p->size());
  EXPECT_TRUE(sameBits(t.eval(0.5, 0, 0), p->eval(0.5, 0, 0)));
  // A dropped graph leaves a program that still evaluates.
  VmProgram d = *p;
  d.dropNodes();
  EXPECT_TRUE(d.nodes().empty());
  EXPECT_TRUE(sameBits(d.eval(0.5, 0, 0), p->eval(0.5, 0, 0)));
}

}  // namespace
}  // namespace emboss
