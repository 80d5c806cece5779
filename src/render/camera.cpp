// The pinhole and orthographic cameras.
#include "render/camera.h"

#include <cmath>

namespace emboss {

Camera::Camera(const CameraSpec& spec, int width, int height) : spec_(spec), width_(width), height_(height) {
  eye_ = {spec.eye.x, spec.eye.y, spec.eye.z};
  const glm::dvec3 target{spec.target.x, spec.target.y, spec.target.z};
  forward_ = glm::normalize(target - eye_);
  glm::dvec3 up{spec.up.x, spec.up.y, spec.up.z};
  if (glm::length(glm::cross(forward_, up)) < 1e-9) up = {0, 0, 1};
  right_ = glm::normalize(glm::cross(forward_, up));
  up_ = glm::cross(right_, forward_);
  aspect_ = static_cast<double>(width) / std::max(1, height);
  halfH_ = spec.type == CameraSpec::Type::Perspective ? std::tan(0.5 * spec.fovDeg * M_PI / 180.0) : 0.5 * spec.height;
}

Ray Camera::rayAt(double sx, double sy) const {
  const double u = (2.0 * sx / width_ - 1.0) * aspect_ * halfH_;
  const double v = (1.0 - 2.0 * sy / height_) * halfH_;
  if (spec_.type == CameraSpec::Type::Ortho) return {eye_ + u * right_ + v * up_, forward_};
  return {eye_, glm::normalize(forward_ + u * right_ + v * up_)};
}

CameraBasis Camera::basis() const {
  CameraBasis b;
  for (int k = 0; k < 3; ++k) b.eye[k] = eye_[k], b.forward[k] = forward_[k], b.right[k] = right_[k], b.up[k] = up_[k];
  b.width = width_, b.height = height_, b.halfH = halfH_, b.aspect = aspect_;
  b.ortho = spec_.type == CameraSpec::Type::Ortho;
  return b;
}

std::optional<glm::dvec2> Camera::project(const glm::dvec3& p) const {
  const glm::dvec3 d = p - eye_;
  const double z = glm::dot(d, forward_);
  double u = glm::dot(d, right_), v = glm::dot(d, up_);
  if (spec_.type == CameraSpec::Type::Perspective) {
    if (z <= 1e-6) return std::nullopt;
    u /= z;
    v /= z;
  }
  const double sx = (u / (aspect_ * halfH_) + 1.0) * 0.5 * width_;
  const double sy = (1.0 - v / halfH_) * 0.5 * height_;
  return glm::dvec2{sx, sy};
}

double Camera::footprint(double t) const {
  if (spec_.type == CameraSpec::Type::Ortho) return 2.0 * halfH_ / height_;
  return 2.0 * halfH_ * t / height_;
}

}  // namespace emboss
