// The sRGB step table.
#include "render/srgb8.h"

#include <algorithm>
#include <bit>

#include "render/shading.h"

namespace emboss {

namespace {

constexpr double kTableMax = 1e6;
constexpr std::uint64_t kNearSteps = 4096;  // ulps around a step where toSrgb8() decides

struct Steps {
  // first[k]: the smallest double x >= 0 whose byte is at least k + 1 (k = 0..254).
  std::array<double, 255> first{};
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
    // Where to start looking: for each bucket (below), the number of steps at or below its lowest
    // value.
    for (size_t b = 0; b < start.size(); ++b) {
      const double x = std::bit_cast<double>((kLowBits + b) << kBucketShift);
      start[b] = static_cast<std::uint8_t>(std::upper_bound(first.begin(), first.end(), x) - first.begin());
    }
  }
  // Buckets of 1/128 of an octave (7 mantissa bits) from 2^-16 to 2^1: a step is at least a few
  // buckets wide below 1, so a lookup scans one or two steps.
  static constexpr int kBucketShift = 52 - 7;
  static constexpr std::uint64_t kLowBits = std::uint64_t{1023 - 16} << 7, kHighBits = std::uint64_t{1023 + 1} << 7;
  std::array<std::uint8_t, kHighBits - kLowBits> start{};
};

const Steps& steps() {
  static const Steps s;
  return s;
}

}  // namespace

std::array<std::uint8_t, 3> toSrgb8Fast(const glm::dvec3& linear) {
  const Steps& s = steps();
  std::array<std::uint8_t, 3> out{};
  for (int i = 0; i < 3; ++i) {
    const double x = linear[i];
    if (!(x <= kTableMax)) return toSrgb8(linear);  // NaN, huge, infinite
    if (x <= 0.0) {  // max(0, x) as toSrgb8 does: negatives (and -0) give byte 0
      out[static_cast<size_t>(i)] = 0;
      continue;
    }
    // The first step above x: from its bucket's count (every bucket's steps scanned), else by
    // binary search (x below 2^-16 or above 2).
    const std::uint64_t bits = std::bit_cast<std::uint64_t>(x), key = bits >> Steps::kBucketShift;
    const double *begin = s.first.data(), *end = begin + s.first.size(), *it;
    if (key >= Steps::kLowBits && key < Steps::kHighBits) {
      it = begin + s.start[key - Steps::kLowBits];
      while (it != end && *it <= x) ++it;
    } else {
      it = std::upper_bound(begin, end, x);
    }
    // Within a few thousand ulps of a step toSrgb8()'s rounding is not monotone: ask it there.
    if ((it != end && std::bit_cast<std::uint64_t>(*it) - bits <= kNearSteps) ||
        (it != begin && bits - std::bit_cast<std::uint64_t>(*(it - 1)) <= kNearSteps))
      return toSrgb8(linear);
    out[static_cast<size_t>(i)] = static_cast<std::uint8_t>(it - begin);
  }
  return out;
}

}  // namespace emboss
