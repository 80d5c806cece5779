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
