// Orbits around the workpiece, for turning it and for the attract mode's slow camera moves.
#include "app/view_orbit.h"

#include <algorithm>
#include <cmath>

namespace emboss {

namespace {
constexpr double kDeg = M_PI / 180.0;
}

Orbit orbitOf(const CameraSpec& c) {
  Orbit o;
  o.target = c.target;
  const double dx = c.eye.x - c.target.x, dy = c.eye.y - c.target.y, dz = c.eye.z - c.target.z;
  o.distance = std::sqrt(dx * dx + dy * dy + dz * dz);
  if (o.distance <= 0) o.distance = 1;
  o.elevationDeg = std::asin(std::clamp(dz / o.distance, -1.0, 1.0)) / kDeg;
  o.azimuthDeg = (std::hypot(dx, dy) < 1e-9) ? 0.0 : std::atan2(dx, -dy) / kDeg;
  return o;
}

CameraSpec cameraAt(const Orbit& o, const CameraSpec& base) {
  CameraSpec c = base;
  const double az = o.azimuthDeg * kDeg, el = std::clamp(o.elevationDeg, -89.0, 89.9) * kDeg;
  c.target = o.target;
  c.eye = {o.target.x + o.distance * std::sin(az) * std::cos(el), o.target.y - o.distance * std::cos(az) * std::cos(el),
           o.target.z + o.distance * std::sin(el)};
  c.up = {-std::sin(az) * std::sin(el), std::cos(az) * std::sin(el), std::cos(el)};
  return c;
}

Orbit mix(const Orbit& a, const Orbit& b, double t) {
  auto l = [t](double x, double y) { return x + (y - x) * t; };
  Orbit o;
  o.azimuthDeg = l(a.azimuthDeg, b.azimuthDeg);
  o.elevationDeg = l(a.elevationDeg, b.elevationDeg);
  o.distance = l(a.distance, b.distance);
  o.target = {l(a.target.x, b.target.x), l(a.target.y, b.target.y), l(a.target.z, b.target.z)};
  return o;
}

double easeInOut(double t) {
  t = std::clamp(t, 0.0, 1.0);
  return t * t * (3.0 - 2.0 * t);
}

}  // namespace emboss
