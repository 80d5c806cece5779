// Linear RGB to 8-bit sRGB by table: the same bytes as toSrgb8() (render/shading.h), faster.
#pragma once

#include <array>
#include <cstdint>

#include <glm/glm.hpp>

namespace emboss {

// toSrgb8() spends three pow() calls a pixel; its output byte is a monotone step function of each
// linear channel, so the 255 steps are found once (by bisection over the ordered doubles, against
// toSrgb8() itself) and a channel becomes a binary search. Returns exactly what toSrgb8() returns
// (checked by tests/render/srgb8_test.cpp): values within 4096 ulps of a step, where toSrgb8()'s
// own rounding is not monotone, and values outside [0, 1e6] (and NaN) go to toSrgb8().
// Thread-safe; the table is built on first use.
std::array<std::uint8_t, 3> toSrgb8Fast(const glm::dvec3& linear);

}  // namespace emboss
