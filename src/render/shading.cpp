// Metal shading: a studio environment (softboxes, a dim room) reflected by a GGX-like lobe.
#include "render/shading.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <mutex>
#include <vector>

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


}  // namespace

namespace {

// The rough lobe: the environment around the mirror direction r, blurred by the roughness with a
// few fixed taps (no randomness: a pixel's colour depends only on its own inputs).
glm::dvec3 roughEnvironment(const glm::dvec3& r, double rough) {
  const glm::dvec3 t = glm::normalize(std::abs(r.z) < 0.9 ? glm::cross(r, glm::dvec3(0, 0, 1)) : glm::cross(r, glm::dvec3(1, 0, 0)));
  const glm::dvec3 b = glm::cross(r, t);
  constexpr int kTaps = 7;
  static const double kOff[kTaps][2] = {{0, 0}, {1, 0}, {-0.5, 0.866}, {-0.5, -0.866}, {0.5, 0.866}, {-1, 0}, {0.5, -0.866}};
  glm::dvec3 spec(0.0);
  double wsum = 0.0;
  for (int i = 0; i < kTaps; ++i) {
    const double w = i == 0 ? 2.0 : 1.0;
    spec += w * environment(glm::normalize(r + 0.45 * rough * (kOff[i][0] * t + kOff[i][1] * b)));
    wsum += w;
  }
  return spec / wsum;
}

// The rough environment prefiltered into an octahedral map over the sphere of directions, one
// per roughness: a pixel then costs one bilinear lookup instead of seven environment evaluations.
// The map is computed by fixed code, so every run and every thread sees the same bits.
class EnvironmentMap {
 public:
  static constexpr int kSize = 256;
  explicit EnvironmentMap(double rough) : texels_(static_cast<size_t>(kSize) * kSize) {
    for (int j = 0; j < kSize; ++j)
      for (int i = 0; i < kSize; ++i) {
        const glm::dvec3 d = decode((i + 0.5) / kSize * 2.0 - 1.0, (j + 0.5) / kSize * 2.0 - 1.0);
        const glm::dvec3 c = roughEnvironment(d, rough);
        texels_[static_cast<size_t>(j) * kSize + i] = glm::vec3(c);
      }
  }
  glm::dvec3 lookup(const glm::dvec3& d) const {
    // Octahedral encoding of a unit vector to [-1, 1]^2.
    const double l1 = std::abs(d.x) + std::abs(d.y) + std::abs(d.z);
    double u = d.x / l1, v = d.y / l1;
    if (d.z < 0) {
      const double ou = u;
      u = (1.0 - std::abs(v)) * (ou >= 0 ? 1.0 : -1.0);
      v = (1.0 - std::abs(ou)) * (v >= 0 ? 1.0 : -1.0);
    }
    const double fx = std::clamp((u + 1.0) * 0.5 * kSize - 0.5, 0.0, kSize - 1.0);
    const double fy = std::clamp((v + 1.0) * 0.5 * kSize - 0.5, 0.0, kSize - 1.0);
    const int x0 = std::min(static_cast<int>(fx), kSize - 2), y0 = std::min(static_cast<int>(fy), kSize - 2);
    const double ax = fx - x0, ay = fy - y0;
    const glm::vec3* row0 = &texels_[static_cast<size_t>(y0) * kSize + x0];
    const glm::vec3* row1 = row0 + kSize;
    const glm::dvec3 top = glm::mix(glm::dvec3(row0[0]), glm::dvec3(row0[1]), ax);
    const glm::dvec3 bottom = glm::mix(glm::dvec3(row1[0]), glm::dvec3(row1[1]), ax);
    return glm::mix(top, bottom, ay);
  }

 private:
  static glm::dvec3 decode(double u, double v) {
    glm::dvec3 d(u, v, 1.0 - std::abs(u) - std::abs(v));
    if (d.z < 0) {
      const double ou = d.x;
      d.x = (1.0 - std::abs(d.y)) * (ou >= 0 ? 1.0 : -1.0);
      d.y = (1.0 - std::abs(ou)) * (d.y >= 0 ? 1.0 : -1.0);
    }
    return glm::normalize(d);
  }
  std::vector<glm::vec3> texels_;
};

const EnvironmentMap& environmentMapFor(double rough) {
  // A few metals, a few roughnesses: the maps live for the program's life.
  thread_local double lastRough = -1.0;
  thread_local const EnvironmentMap* last = nullptr;
  if (last && lastRough == rough) return *last;
  static std::mutex mutex;
  static std::map<double, std::unique_ptr<EnvironmentMap>> maps;
  std::lock_guard lock(mutex);
  auto& slot = maps[rough];
  if (!slot) slot = std::make_unique<EnvironmentMap>(rough);
  lastRough = rough;
  last = slot.get();
  return *last;
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
  const double m = 1.0 - std::clamp(cosV, 0.0, 1.0);
  const double m2 = m * m;
  const glm::dvec3 fresnel = f0 + (glm::dvec3(1.0) - f0) * (m2 * m2 * m);
  const glm::dvec3 spec = environmentMapFor(s.metal.roughness).lookup(r);
  // A little diffuse from the metal's oxide skin keeps the dark side from going black.
  const double lambert = std::max(0.0, glm::dot(n, glm::dvec3(-0.4, 0.6, 0.7) / std::sqrt(1.01)));
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
