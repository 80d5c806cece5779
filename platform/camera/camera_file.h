// The file camera: a CameraSource whose still is a PNG file (tests, demos, machines without a camera).
#pragma once

#include <filesystem>
#include <memory>

#include "devices/camera.h"
#include "util/result.h"

namespace emboss {

class FileCamera final : public CameraSource {
 public:
  explicit FileCamera(std::filesystem::path png) : path_(std::move(png)) {}
  std::string name() const override { return "file: " + path_.string(); }
  // Reads the file on every call, so a new photo can be dropped in place while the kiosk runs.
  Result<Image> capture() override;

 private:
  std::filesystem::path path_;
};

// Checks that the PNG reads now, so a wrong path fails at start-up rather than at the first still.
Result<std::unique_ptr<CameraSource>> openFileCamera(const std::filesystem::path& png);

}  // namespace emboss
