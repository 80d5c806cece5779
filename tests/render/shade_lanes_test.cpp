// shadeMetal over a batch of hits in SIMD lanes gives, hit by hit, the bits of shadeMetal one hit at
// a time: for every metal and tinge, on every SIMD target this machine has and the build compiled.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>
#include <vector>

#include "hwy/targets.h"
#include "render/shade_lanes.h"
#include "render/shading.h"
#include "tools/metal.h"

namespace emboss {
namespace {

bool sameBits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

glm::dvec3 randomUnit(std::mt19937& rng) {
  std::normal_distribution<double> g;
  for (;;) {
    const glm::dvec3 v(g(rng), g(rng), g(rng));
    const double len = glm::length(v);
    if (len > 1e-3) return v / len;
  }
}

struct Hit {
  glm::dvec3 p, n, v;
  double cavity;
};

// Hits as the renderer makes them and stranger: points over a large sheet (negative coordinates
// too), normals mostly up and some facing away from the eye, views mostly down and some grazing,
// cavities from 0 to past 1.
std::vector<Hit> randomHits(unsigned seed, int count) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<Hit> hits;
  for (int i = 0; i < count; ++i) {
    Hit h;
    h.p = glm::dvec3(-160.0 + 320.0 * u(rng), -120.0 + 240.0 * u(rng), -1.5 + 3.0 * u(rng));
    h.n = randomUnit(rng);
    if (i % 3 != 0) h.n.z = std::abs(h.n.z), h.n = glm::normalize(h.n + glm::dvec3(0, 0, 2));
    h.v = randomUnit(rng);
    if (i % 4 != 0) h.v.z = -std::abs(h.v.z) - (i % 8 == 1 ? 0.0 : 1.0), h.v = glm::normalize(h.v);
    const int kind = i % 5;
    h.cavity = kind == 0 ? 0.0 : kind == 1 ? 1.0 : kind == 2 ? 1.3 * u(rng) : u(rng);
    hits.push_back(h);
  }
  return hits;
}

// Every metal with every tinge, batches of every length up to a full one, against one call a hit;
// returns the hits compared.
long compareAll(const char* target) {
  long compared = 0;
  for (const Metal& metal : metals())
    for (const Tinge& tinge : tinges()) {
      const ShadingParams s = sheetShading(metal.name, tinge.name, 0.4);
      const std::vector<Hit> hits = randomHits(17u + static_cast<unsigned>(compared), 3 * ShadeBatch::kCapacity);
      size_t next = 0;
      for (int len : {1, 2, 3, 5, 7, 8, 13, 31, ShadeBatch::kCapacity, 45, 33, 9, 17}) {
        ShadeBatch b;
        b.n = 0;
        std::vector<const Hit*> in;
        for (int k = 0; k < len; ++k) {
          const Hit& h = hits[next++ % hits.size()];
          const int j = b.n++;
          b.px[j] = h.p.x, b.py[j] = h.p.y, b.pz[j] = h.p.z;
          b.nx[j] = h.n.x, b.ny[j] = h.n.y, b.nz[j] = h.n.z;
          b.vx[j] = h.v.x, b.vy[j] = h.v.y, b.vz[j] = h.v.z;
          b.cavity[j] = h.cavity;
          in.push_back(&h);
        }
        shadeMetal(s, b);
        for (int j = 0; j < len; ++j) {
          const Hit& h = *in[static_cast<size_t>(j)];
          const glm::dvec3 want = shadeMetal(s, h.p, h.n, h.v, h.cavity);
          const bool same = sameBits(b.r[j], want.r) && sameBits(b.g[j], want.g) && sameBits(b.b[j], want.b);
          EXPECT_TRUE(same) << target << ", " << metal.name << " with " << tinge.name << ", hit " << j << " of " << len
                            << ": lanes " << b.r[j] << " " << b.g[j] << " " << b.b[j] << ", one at a time " << want.r
                            << " " << want.g << " " << want.b;
          if (!same) return compared;
          ++compared;
        }
      }
    }
  return compared;
}

TEST(ShadeLanes, EveryTargetGivesTheBitsOfOneHitAtATime) {
  int targets = 0;
  for (const int64_t target : hwy::SupportedAndGeneratedTargets()) {
    hwy::SetSupportedTargetsForTest(target);
    const long compared = compareAll(hwy::TargetName(target));
    EXPECT_GT(compared, 4000) << hwy::TargetName(target);
    ++targets;
  }
  hwy::SetSupportedTargetsForTest(0);
  EXPECT_GE(targets, 1);
}

// The lanes use the hammer's dimples and the tinge as the metals have them: at least one metal
// has dimples and one tinge has strength, so the comparison above covers those branches.
TEST(ShadeLanes, TheComparisonCoversDimplesAndTinges) {
  bool hammer = false, tinge = false;
  for (const Metal& m : metals()) hammer = hammer || m.hammer > 0;
  for (const Tinge& t : tinges()) tinge = tinge || t.strength > 0;
  EXPECT_TRUE(hammer);
  EXPECT_TRUE(tinge);
}

}  // namespace
}  // namespace emboss
