// The camera's rays through many image points at once, each clipped to a box, in SIMD lanes
// (Highway, the instruction set chosen at run time): the bits Camera::rayAt() and clipRay() give
// one ray at a time, and the start of its walk on the field tracer's grid. A ray's set-up is a
// chain of a square root and divisions, each waiting on the last; lanes take several rays' chains
// side by side (Renderer::findFieldHits(), docs/rendering.md, "Rays in lanes").
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "frep/box.h"
#include "render/camera.h"

namespace emboss {

// The rays' starts, a value per ray (resized by raysInLanes()).
struct RayStarts {
  enum State : std::uint8_t { kMisses = 0, kClipped = 1, kAlone = 2 };
  std::vector<double> ox, oy, oz, dx, dy, dz;  // the ray
  std::vector<double> g0, g1;                  // floor(t0 / h) and ceil(t1 / h), [t0, t1] the clip
  std::vector<double> rx0, ry0, rx1, ry1;      // the (x, y) box of the points at g0 h and g1 h
  // kMisses: the ray misses the box; kClipped: the values above hold; kAlone: a component of the
  // direction is under 1e-15 (clipRay() takes it apart), the ray is set up by the caller alone.
  std::vector<std::uint8_t> state;
  void resize(size_t n);
};

// The rays through the image points (sx[i], sy[i]), i < n, clipped to `clip`, their grid points
// t = q h8 (h8 = h / 16) from q0 = 16 g0 to q1 = 16 g1, and their reach, into `out`. The same bits
// as Camera::rayAt(), clipRay() and Renderer::beginWalk() (tests/render/ray_lanes_test.cpp).
void raysInLanes(const CameraBasis& camera, const Box3& clip, double h, double h8, const double* sx, const double* sy,
                 int n, RayStarts& out);

}  // namespace emboss
