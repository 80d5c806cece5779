// Turning the workpiece: the camera orbits the piece (azimuth around the sheet's normal, elevation above it).
#pragma once

#include "scene/scene.h"

namespace emboss {

// Angles in degrees. Azimuth 0 looks from -y (the visitor's side of the bench) and grows toward +x;
// elevation 90 looks straight down the sheet's normal (+z).
struct Orbit {
  double azimuthDeg = 0, elevationDeg = 70, distance = 200;
  Vec3 target;
};

Orbit orbitOf(const CameraSpec& camera);
// `base` with its eye, target and up replaced by the orbit's (type, field of view kept). The up
// vector is the direction of rising elevation, so the picture never rolls.
CameraSpec cameraAt(const Orbit& orbit, const CameraSpec& base);
// Component-wise interpolation, t in 0..1.
Orbit mix(const Orbit& a, const Orbit& b, double t);
// 0..1 -> 0..1, slow at both ends.
double easeInOut(double t);

}  // namespace emboss
