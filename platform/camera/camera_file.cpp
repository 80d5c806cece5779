// The file camera: the still is read from a PNG, with the path in every message.
#include "camera/camera_file.h"

namespace emboss {

Result<Image> FileCamera::capture() {
  auto img = readPng(path_);
  if (!img) return fail("camera (file): " + img.error());
  return img;
}

Result<std::unique_ptr<CameraSource>> openFileCamera(const std::filesystem::path& png) {
  auto cam = std::make_unique<FileCamera>(png);
  if (auto img = cam->capture(); !img) return fail(img.error());
  return std::unique_ptr<CameraSource>(std::move(cam));
}

}  // namespace emboss
