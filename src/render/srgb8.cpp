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
  }
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
    const auto it = std::upper_bound(s.first.begin(), s.first.end(), x);
    // Within a few thousand ulps of a step toSrgb8()'s rounding is not monotone: ask it there.
    const std::uint64_t bits = std::bit_cast<std::uint64_t>(x);
    if ((it != s.first.end() && std::bit_cast<std::uint64_t>(*it) - bits <= kNearSteps) ||
        (it != s.first.begin() && bits - std::bit_cast<std::uint64_t>(*(it - 1)) <= kNearSteps))
      return toSrgb8(linear);
    out[static_cast<size_t>(i)] = static_cast<std::uint8_t>(it - s.first.begin());
  }
  return out;
}

}  // namespace emboss
