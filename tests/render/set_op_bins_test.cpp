// The set operations' bins name exactly the operations whose support meets a box or holds a point,
// in the operations' order, and read fewer than all of them over a pile.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <utility>
#include <vector>

#include "render/set_op_bins.h"

namespace emboss {
namespace {

struct Pile {
  std::vector<Box2> supports;
};

// `n` supports of 2 to 14 mm round a 60 x 40 mm motif, some on its edges, a few of them alike.
Pile pileOf(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> x(-30.0, 30.0), y(-20.0, 20.0), size(1.0, 7.0);
  Pile p;
  for (int k = 0; k < n; ++k) {
    Box2 b;
    if (k % 9 == 8) {
      b = p.supports[static_cast<size_t>(k - 1)];  // a punch dragged over one spot
    } else {
      const double cx = x(rng), cy = y(rng), hx = size(rng), hy = size(rng);
      b = Box2{cx - hx, cy - hy, cx + hx, cy + hy};
    }
    p.supports.push_back(b);
  }
  return p;
}

// The k the bins under `box` name (a superset), and those the exact queries name.
std::vector<std::uint32_t> named(const SetOpBins& bins, const Box2& box) {
  std::vector<std::uint32_t> out;
  bins.under(box, [&](std::uint32_t k) { out.push_back(k); });
  return out;
}
std::vector<std::uint32_t> meeting(const SetOpBins& bins, const Box2& box) {
  std::vector<std::uint32_t> out;
  bins.meeting(box, [&](std::uint32_t k) { out.push_back(k); });
  return out;
}
std::vector<std::uint32_t> holding(const SetOpBins& bins, double x, double y) {
  std::vector<std::uint32_t> out;
  bins.holding(x, y, [&](std::uint32_t k) { out.push_back(k); });
  return out;
}

TEST(SetOpBins, NameTheOperationsThatMeetABoxInOrder) {
  for (int n : {3, 16, 93, 200}) {
    const Pile p = pileOf(n, 7u + static_cast<unsigned>(n));
    SetOpBins bins;
    bins.build(p.supports);
    ASSERT_EQ(bins.size(), p.supports.size());
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> x(-45.0, 45.0), y(-35.0, 35.0), size(0.0, 6.0);
    size_t named_total = 0, meeting_total = 0;
    for (int trial = 0; trial < 3000; ++trial) {
      const double cx = x(rng), cy = y(rng);
      // Boxes of every size, points (a hit's normal), and boxes on a support's very edge.
      Box2 box = trial % 3 == 0 ? Box2{cx, cy, cx, cy} : Box2{cx, cy, cx + size(rng), cy + size(rng)};
      if (trial % 7 == 0) {
        const Box2& s = p.supports[static_cast<size_t>(trial) % p.supports.size()];
        box = Box2{s.x1, s.y1, s.x1 + 1.0, s.y1 + 1.0};
      }
      const std::vector<std::uint32_t> got = named(bins, box);
      for (size_t i = 1; i < got.size(); ++i) ASSERT_LT(got[i - 1], got[i]) << "n " << n << ": not ascending";
      std::vector<std::uint32_t> meets, holds;
      for (size_t k = 0; k < p.supports.size(); ++k) {
        if (p.supports[k].overlaps(box)) {
          meets.push_back(static_cast<std::uint32_t>(k));
          ASSERT_TRUE(std::binary_search(got.begin(), got.end(), static_cast<std::uint32_t>(k)))
              << "n " << n << ": support " << k << " meets the box and its bins do not name it";
        }
        if (p.supports[k].contains(cx, cy)) holds.push_back(static_cast<std::uint32_t>(k));
      }
      ASSERT_EQ(meeting(bins, box), meets) << "n " << n;
      ASSERT_EQ(holding(bins, cx, cy), holds) << "n " << n;
      meeting_total += meets.size();
      named_total += got.size();
    }
    // A support's own corners: it holds them.
    for (std::uint32_t k = 0; k < p.supports.size(); ++k)
      for (const auto& [x, y] : {std::pair{p.supports[k].x0, p.supports[k].y0}, std::pair{p.supports[k].x1, p.supports[k].y1}}) {
        const std::vector<std::uint32_t> h = holding(bins, x, y);
        ASSERT_TRUE(std::binary_search(h.begin(), h.end(), k)) << "n " << n << ": support " << k << "'s corner";
      }
    if (n < static_cast<int>(SetOpBins::kFewest)) {
      EXPECT_EQ(named_total, 3000u * static_cast<size_t>(n)) << "few operations: every one is named";
    } else {
      // Over a pile the bins name a fraction of the operations (a superset of those that meet).
      EXPECT_LT(named_total, 3000u * static_cast<size_t>(n) / 3) << "n " << n;
      EXPECT_GE(named_total, meeting_total);
    }
  }
}

TEST(SetOpBins, AnEmptyOrDegenerateAreaNamesEveryOperation) {
  SetOpBins bins;
  bins.build({});
  EXPECT_TRUE(named(bins, Box2{0, 0, 1, 1}).empty());
  EXPECT_TRUE(meeting(bins, Box2{0, 0, 1, 1}).empty());
  // Every support the same point: a grid of one bin.
  bins.build(std::vector<Box2>(20, Box2{2.0, 3.0, 2.0, 3.0}));
  EXPECT_EQ(meeting(bins, Box2{2.0, 3.0, 2.0, 3.0}).size(), 20u);
  EXPECT_EQ(meeting(bins, Box2{-5.0, -5.0, 9.0, 9.0}).size(), 20u);
  EXPECT_EQ(holding(bins, 2.0, 3.0).size(), 20u);
  EXPECT_TRUE(holding(bins, 2.0, 3.5).empty());
}

}  // namespace
}  // namespace emboss
