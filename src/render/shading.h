// Shading: how polished metal under a museum's lights looks, from a surface point and its normal.
#pragma once

#include <array>

#include <glm/glm.hpp>

#include "tools/metal.h"

namespace emboss {

// Everything the shading needs that does not change from pixel to pixel.
struct ShadingParams {
  Metal metal;
  Tinge tinge;
  double frontZ = 0.5;      // z of the untouched front face (the tinge gathers below it)
  double tingeDepth = 0.6;  // mm below the front face where the tinge is at full strength
};

// Linear RGB of a surface point seen along `view` (unit, from the eye) with unit normal `n`.
// Deterministic: depends on nothing but its arguments.
glm::dvec3 shadeMetal(const ShadingParams& s, const glm::dvec3& p, const glm::dvec3& n, const glm::dvec3& view);
// The backdrop (dark velvet) behind the piece, for pixel (x, y) of a w x h image.
glm::dvec3 backdrop(int x, int y, int w, int h);
// Linear to 8-bit sRGB with a gentle filmic shoulder so highlights do not clip harshly.
std::array<std::uint8_t, 3> toSrgb8(const glm::dvec3& linear);

}  // namespace emboss
