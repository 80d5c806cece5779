// The metal and tinge tables.
#include "tools/metal.h"

#include <algorithm>
#include <cmath>

namespace emboss {

namespace {

Metal makeMetal(std::string_view name, std::array<double, 3> eta, std::array<double, 3> k, double roughness,
                double hammer, double ductility, double hardness) {
  Metal m{name, eta, k, roughness, hammer, ductility, hardness, {}};
  for (int c = 0; c < 3; ++c) m.f0[c] = fresnelConductor(1.0, eta[c], k[c]);
  return m;
}

}  // namespace

double fresnelConductor(double cosTheta, double eta, double k) {
  // The exact expression for a conductor under unpolarised light (as in pbrt-v3's FrConductor).
  const double c = std::clamp(cosTheta, 0.0, 1.0);
  const double c2 = c * c, s2 = 1.0 - c2;
  const double eta2 = eta * eta, k2 = k * k;
  const double t0 = eta2 - k2 - s2;
  const double a2b2 = std::sqrt(t0 * t0 + 4.0 * eta2 * k2);
  const double t1 = a2b2 + c2;
  const double a = std::sqrt(std::max(0.0, 0.5 * (a2b2 + t0)));
  const double t2 = 2.0 * c * a;
  const double rs = (t1 - t2) / (t1 + t2);
  const double t3 = c2 * a2b2 + s2 * s2;
  const double t4 = t2 * s2;
  const double rp = rs * (t3 - t4) / (t3 + t4);
  return 0.5 * (rp + rs);
}

const std::array<Metal, 4>& metals() {
  // n and k at 630, 532 and 465 nm, interpolated linearly from pbrt-v4's measured tables (Cu, CuZn
  // for brass, Ag, Al). Roughness (GGX alpha) and the hammer's slope are this project's choices for
  // a polished, planished sheet: sharp enough that the face mirrors the studio's lights and each
  // dimple glints (at twice these roughnesses the face was one flat colour).
  static const std::array<Metal, 4> kMetals = {{
      makeMetal("copper", {0.2459, 1.0723, 1.1569}, {3.3784, 2.5907, 2.4572}, 0.048, 0.068, 1.00, 0.45),
      makeMetal("brass", {0.4450, 0.5682, 0.9470}, {3.5220, 2.5880, 1.9200}, 0.040, 0.053, 0.70, 0.75),
      makeMetal("silver", {0.1342, 0.1297, 0.1395}, {3.9628, 3.1942, 2.6135}, 0.028, 0.045, 0.90, 0.55),
      makeMetal("aluminium", {1.3571, 0.8843, 0.6605}, {7.5878, 6.4700, 5.6536}, 0.064, 0.075, 0.85, 0.35),
  }};
  return kMetals;
}

std::optional<Metal> metalByName(std::string_view name) {
  for (const Metal& m : metals())
    if (m.name == name) return m;
  if (name == "aluminum") return metals()[3];
  return std::nullopt;
}

const std::array<Tinge, 5>& tinges() {
  static const std::array<Tinge, 5> kTinges = {{
      {"none", {1.0, 1.0, 1.0}, 0.0},
      {"black", {0.06, 0.055, 0.05}, 0.85},
      {"brown", {0.35, 0.16, 0.07}, 0.75},
      {"green", {0.20, 0.45, 0.30}, 0.70},
      {"golden", {1.00, 0.76, 0.30}, 0.60},
  }};
  return kTinges;
}

std::optional<Tinge> tingeByName(std::string_view name) {
  for (const Tinge& t : tinges())
    if (t.name == name) return t;
  return std::nullopt;
}

}  // namespace emboss
