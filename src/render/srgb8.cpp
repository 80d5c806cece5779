// The sRGB step table.
#include "render/srgb8.h"

#include <algorithm>
#include <bit>
#include <limits>
#include <vector>

#include "render/shading.h"

namespace emboss {

namespace {

constexpr double kTableMax = 1e6;

struct Steps {
  // first[k]: the smallest double x >= 0 whose byte is at least k + 1 (k = 0..254).
  std::array<double, 255> first{};
  // Where to start looking: for each bucket, the number of steps at or below its lowest value.
  std::array<std::int64_t, Srgb8Table::kHighBits - Srgb8Table::kLowBits> start{};
  // The steps as Srgb8Table lays them out (0 first, infinities after).
  std::vector<double> padded;
  Srgb8Table table;
  Steps() {
    auto byteOf = [](double x) { return toSrgb8(glm::dvec3(x, 0.0, 0.0))[0]; };
    for (int k = 1; k <= 255; ++k) {
      // Non-negative doubles are ordered like their bit patterns.
      std::uint64_t lo = 0, hi = std::bit_cast<std::uint64_t>(kTableMax);
      while (lo < hi) {
        const std::uint64_t mid = lo + (hi - lo) / 2;
        if (byteOf(std::bit_cast<double>(mid)) >= k)
          hi = mid;
        else
          lo = mid + 1;
      }
      first[static_cast<size_t>(k - 1)] = std::bit_cast<double>(lo);
    }
    auto below = [&](double x) { return static_cast<std::int64_t>(std::upper_bound(first.begin(), first.end(), x) - first.begin()); };
    int scan = 0;
    for (size_t b = 0; b < start.size(); ++b) {
      const double x = std::bit_cast<double>(static_cast<std::uint64_t>(Srgb8Table::kLowBits + static_cast<std::int64_t>(b)) << Srgb8Table::kBucketShift);
      start[b] = below(x);
      // The steps inside the bucket: those at or below its highest value.
      const double top = std::bit_cast<double>(
          (static_cast<std::uint64_t>(Srgb8Table::kLowBits + static_cast<std::int64_t>(b) + 1) << Srgb8Table::kBucketShift) - 1);
      scan = std::max(scan, static_cast<int>(below(top) - start[b]));
    }
    padded.assign(256 + static_cast<size_t>(scan) + 2, std::numeric_limits<double>::infinity());
    padded[0] = 0.0;
    std::copy(first.begin(), first.end(), padded.begin() + 1);
    table = Srgb8Table{padded.data(), start.data(), scan};
  }
};

const Steps& steps() {
  static const Steps s;
  return s;
}

}  // namespace

const Srgb8Table& srgb8Table() { return steps().table; }

std::uint8_t toSrgb8Channel(double x) {
  const Steps& s = steps();
  const auto exact = [&] { return toSrgb8(glm::dvec3(x, 0.0, 0.0))[0]; };
  if (!(x <= kTableMax)) return exact();  // NaN, huge, infinite
  if (x <= 0.0) return 0;                 // max(0, x) as toSrgb8 does: negatives (and -0) give byte 0
  // The first step above x: from its bucket's count (every bucket's steps scanned), else by
  // binary search (x below 2^-16 or above 2).
  const std::uint64_t bits = std::bit_cast<std::uint64_t>(x);
  const auto key = static_cast<std::int64_t>(bits >> Srgb8Table::kBucketShift);
  const double *begin = s.first.data(), *end = begin + s.first.size(), *it;
  if (key >= Srgb8Table::kLowBits && key < Srgb8Table::kHighBits) {
    it = begin + s.start[static_cast<size_t>(key - Srgb8Table::kLowBits)];
    while (it != end && *it <= x) ++it;
  } else {
    it = std::upper_bound(begin, end, x);
  }
  // Within a few thousand ulps of a step toSrgb8()'s rounding is not monotone: ask it there.
  constexpr auto near = static_cast<std::uint64_t>(Srgb8Table::kNearSteps);
  if ((it != end && std::bit_cast<std::uint64_t>(*it) - bits <= near) || (it != begin && bits - std::bit_cast<std::uint64_t>(*(it - 1)) <= near))
    return exact();
  return static_cast<std::uint8_t>(it - begin);
}

std::array<std::uint8_t, 3> toSrgb8Fast(const glm::dvec3& linear) {
  return {toSrgb8Channel(linear[0]), toSrgb8Channel(linear[1]), toSrgb8Channel(linear[2])};
}

}  // namespace emboss
