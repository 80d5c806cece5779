// Linear RGB to 8-bit sRGB by table: the same bytes as toSrgb8() (render/shading.h), faster.
#pragma once

#include <array>
#include <cstdint>

#include <glm/glm.hpp>

namespace emboss {

// toSrgb8() spends three pow() calls a pixel; its output byte is a monotone step function of each
// linear channel (the curve is the same for each, and each channel's alone), so the 255 steps are
// found once (by bisection over the ordered doubles, against toSrgb8() itself) and a channel
// becomes a lookup. Returns exactly what toSrgb8() returns (checked by tests/render/srgb8_test.cpp):
// values within 4096 ulps of a step, where toSrgb8()'s own rounding is not monotone, and values
// outside [0, 1e6] (and NaN) go to toSrgb8(). Thread-safe; the table is built on first use.
std::array<std::uint8_t, 3> toSrgb8Fast(const glm::dvec3& linear);

// toSrgb8()'s byte of one linear channel value, by the table.
std::uint8_t toSrgb8Channel(double linear);

// toSrgb8()'s bytes of n linear channel values (any channels, in any order: out[i] is the byte of
// linear[i]), in SIMD lanes (Highway, the instruction set chosen at run time) where whole vectors
// fill: a row's pixels at once. The same bytes as toSrgb8Channel() of each.
void toSrgb8Channels(const double* linear, int n, std::uint8_t* out);

// The table, for the lanes (srgb8_lanes.cpp).
struct Srgb8Table {
  // Buckets of 1/128 of an octave (7 mantissa bits) from 2^-16 to 2^1: a double's bits shifted
  // right by kBucketShift, less kLowBits, is its bucket where that lies in [0, kHighBits - kLowBits).
  static constexpr int kBucketShift = 52 - 7;
  static constexpr std::int64_t kLowBits = std::int64_t{1023 - 16} << 7, kHighBits = std::int64_t{1023 + 1} << 7;
  // Within this many ulps of a step toSrgb8() decides.
  static constexpr std::int64_t kNearSteps = 4096;
  // steps[k] (k = 1..255): the smallest double x >= 0 whose byte is at least k; steps[0] = 0, and
  // past steps[255] infinities (at least `scan` + 1 of them). A value's byte is the number of
  // steps[1..255] at or below it.
  const double* steps = nullptr;
  // start[b]: the number of steps at or below bucket b's lowest value.
  const std::int64_t* start = nullptr;
  // The most steps within one bucket: a value's byte is start[b] plus the count of
  // steps[start[b] + 1 .. start[b] + scan] at or below it.
  int scan = 0;
};
const Srgb8Table& srgb8Table();

}  // namespace emboss
