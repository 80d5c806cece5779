// Homographies: the projective map between a photographed sheet and its flat rectangle.
#pragma once

#include <array>
#include <optional>

#include "frep/operation.h"

namespace emboss {

// A 3x3 projective map of the plane, row-major, acting on (x, y, 1).
struct Homography {
  std::array<double, 9> m{1, 0, 0, 0, 1, 0, 0, 0, 1};

  Vec2 apply(const Vec2& p) const;
  // nullopt when the map is singular.
  std::optional<Homography> inverse() const;
  // The map taking src[i] to dst[i] (four points, no three collinear), or nullopt when degenerate.
  static std::optional<Homography> fromQuad(const std::array<Vec2, 4>& src, const std::array<Vec2, 4>& dst);
};

// Composition: (a * b).apply(p) == a.apply(b.apply(p)).
Homography operator*(const Homography& a, const Homography& b);

}  // namespace emboss
