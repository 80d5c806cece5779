// Metal shading: a studio environment (softboxes, a dim room) reflected by a GGX-like lobe.
#include "render/shading.h"

#include <algorithm>
#include <cmath>

namespace emboss {

namespace {

// Radiance of the studio around the bench, by direction (z is toward the viewer's side of the
// sheet, y up the bench). Two softboxes high above-left and above-right, a long strip light
// above, a warm floor bounce and a dark room: the mix that makes chased metal read.
glm::dvec3 environment(const glm::dvec3& d) {
  glm::dvec3 c = glm::mix(glm::dvec3(0.030, 0.028, 0.026), glm::dvec3(0.16, 0.15, 0.14), std::clamp(0.5 + 0.5 * d.y, 0.0, 1.0));
  auto box = [&](const glm::dvec3& center, double size, double power, double soft = 0.03) {
    const double k = glm::dot(d, glm::normalize(center));
    const double edge = std::cos(size);
    if (k <= edge - soft) return 0.0;
    return power * std::clamp((k - (edge - soft)) / soft, 0.0, 1.0);
  };
  // A large, soft overhead panel in front of the bench: what a flat sheet mirrors from where a
  // visitor stands, so the untouched metal reads bright with a falloff rather than dull.
  c += glm::dvec3(1.0, 0.96, 0.90) * box({-0.08, 0.45, 0.89}, 0.30, 0.85, 0.12);
  c += glm::dvec3(1.0, 0.97, 0.92) * box({-0.55, 0.65, 0.55}, 0.33, 5.0);
  c += glm::dvec3(0.90, 0.95, 1.00) * box({0.65, 0.45, 0.60}, 0.25, 3.0);
  c += glm::dvec3(1.0, 1.0, 1.0) * box({0.0, 0.9, 0.45}, 0.12, 6.0);
  // Floor bounce from below the bench.
  c += glm::dvec3(0.10, 0.07, 0.05) * std::clamp(-d.y, 0.0, 1.0);
  return c;
}

glm::dvec3 schlick(const glm::dvec3& f0, double cosTheta) {
  const double m = std::pow(1.0 - std::clamp(cosTheta, 0.0, 1.0), 5.0);
  return f0 + (glm::dvec3(1.0) - f0) * m;
}

}  // namespace

glm::dvec3 shadeMetal(const ShadingParams& s, const glm::dvec3& p, const glm::dvec3& nIn, const glm::dvec3& view) {
  glm::dvec3 n = nIn;
  if (glm::dot(n, view) > 0) n = -n;  // seen from behind: light the face we see
  const glm::dvec3 r = glm::reflect(view, n);
  const double cosV = std::max(1e-4, -glm::dot(view, n));
  glm::dvec3 f0(s.metal.f0[0], s.metal.f0[1], s.metal.f0[2]);
  // The tinge (patina) gathers in the hollows: below the front face, fading in over tingeDepth.
  if (s.tinge.strength > 0) {
    const double depth = std::clamp((s.frontZ - p.z) / s.tingeDepth, 0.0, 1.0);
    const double k = s.tinge.strength * (0.25 + 0.75 * depth);
    f0 = glm::mix(f0, f0 * glm::dvec3(s.tinge.color[0], s.tinge.color[1], s.tinge.color[2]), k);
  }
  const glm::dvec3 fresnel = schlick(f0, cosV);
  // A rough lobe approximated by blending the mirror direction toward the normal, sampled at a few
  // fixed directions (no randomness: a pixel's colour depends only on its own inputs).
  const double rough = s.metal.roughness;
  glm::dvec3 spec(0.0);
  const glm::dvec3 t = glm::normalize(glm::abs(r.z) < 0.9 ? glm::cross(r, glm::dvec3(0, 0, 1)) : glm::cross(r, glm::dvec3(1, 0, 0)));
  const glm::dvec3 b = glm::cross(r, t);
  constexpr int kTaps = 7;
  static const double kOff[kTaps][2] = {{0, 0}, {1, 0}, {-0.5, 0.866}, {-0.5, -0.866}, {0.5, 0.866}, {-1, 0}, {0.5, -0.866}};
  double wsum = 0.0;
  for (int i = 0; i < kTaps; ++i) {
    const double w = i == 0 ? 2.0 : 1.0;
    glm::dvec3 d = glm::normalize(r + 0.45 * rough * (kOff[i][0] * t + kOff[i][1] * b));
    if (glm::dot(d, n) < 0) d = glm::normalize(d - 2.0 * glm::dot(d, n) * n);
    spec += w * environment(d);
    wsum += w;
  }
  spec /= wsum;
  // A little diffuse from the metal's oxide skin keeps the dark side from going black.
  const double lambert = std::max(0.0, glm::dot(n, glm::normalize(glm::dvec3(-0.4, 0.6, 0.7))));
  return fresnel * spec + f0 * 0.04 * (0.3 + lambert);
}

glm::dvec3 backdrop(int x, int y, int w, int h) {
  const double u = (x + 0.5) / w - 0.5, v = (y + 0.5) / h - 0.5;
  const double vignette = std::clamp(1.0 - 1.3 * (u * u + v * v), 0.0, 1.0);
  return glm::dvec3(0.018, 0.020, 0.026) * (0.4 + 0.6 * vignette);
}

std::array<std::uint8_t, 3> toSrgb8(const glm::dvec3& linear) {
  std::array<std::uint8_t, 3> out{};
  for (int i = 0; i < 3; ++i) {
    double c = std::max(0.0, linear[i]);
    c = c / (1.0 + 0.25 * c);  // soft shoulder
    c = c <= 0.0031308 ? 12.92 * c : 1.055 * std::pow(c, 1.0 / 2.4) - 0.055;
    out[i] = static_cast<std::uint8_t>(std::clamp(std::lround(c * 255.0), 0L, 255L));
  }
  return out;
}

}  // namespace emboss
