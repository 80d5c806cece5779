// The camera: rays through pixel centres, and the projection of points back to pixels.
#pragma once

#include <optional>

#include <glm/glm.hpp>

#include "scene/scene.h"

namespace emboss {

struct Ray {
  glm::dvec3 origin;
  glm::dvec3 dir;  // unit length
};

// A camera as Camera::rayAt() reads it (Camera::basis()), for the rays set up in SIMD lanes
// (ray_lanes.h).
struct CameraBasis {
  double eye[3] = {0, 0, 0}, forward[3] = {0, 0, -1}, right[3] = {1, 0, 0}, up[3] = {0, 1, 0};
  double width = 1, height = 1;  // the image's, in pixels
  double halfH = 1, aspect = 1;
  bool ortho = false;
};

class Camera {
 public:
  Camera(const CameraSpec& spec, int width, int height);
  int width() const { return width_; }
  int height() const { return height_; }
  // The ray through the centre of pixel (px, py), row 0 at the top.
  Ray ray(int px, int py) const { return rayAt(px + 0.5, py + 0.5); }
  Ray rayAt(double sx, double sy) const;
  // Where a point of space lands on the image (pixel units), if it is in front of the camera.
  std::optional<glm::dvec2> project(const glm::dvec3& p) const;
  // The size in mm of one pixel at distance `t` along a ray (for step sizes and dirty margins).
  double footprint(double t) const;
  const CameraSpec& spec() const { return spec_; }
  // What rayAt() reads, for the rays taken in SIMD lanes (ray_lanes.h).
  CameraBasis basis() const;

 private:
  CameraSpec spec_;
  int width_, height_;
  glm::dvec3 eye_, forward_, right_, up_;
  double halfH_ = 1.0;  // perspective: tan(fov/2); ortho: half the view height in mm
  double aspect_ = 1.0;
};

}  // namespace emboss
