// The scene file: workpiece, deformation model, metal, camera and operations, as JSON.
#pragma once

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "frep/model.h"
#include "util/durable_file.h"
#include "util/result.h"

namespace emboss {

struct CameraSpec {
  enum class Type { Perspective, Ortho };
  Type type = Type::Perspective;
  Vec3 eye{0, -60, 160};
  Vec3 target{0, 0, 0};
  Vec3 up{0, 1, 0};
  double fovDeg = 35.0;
  double height = 100.0;  // ortho: the height of the view in mm
  bool operator==(const CameraSpec&) const = default;
};

// A scene as read from a file. `operations` are all the file's operations, in order.
struct Scene {
  Deformation deformation = Deformation::Sheet;
  std::shared_ptr<const Workpiece> workpiece;
  std::string metal = "copper";
  std::string tinge = "none";
  CameraSpec camera;
  bool cameraGiven = false;  // false: the camera was framed on the workpiece by default
  std::vector<Operation> operations;
  std::string title;         // optional, for attract pieces and exports

  // A model of the workpiece with every operation applied.
  Result<Model> makeModel() const;
};

// A camera that frames the workpiece's bounds, looking at its front from a little below.
CameraSpec defaultCamera(const Box3& bounds);

// Parses a scene; `name` prefixes every message ("piece.json: operations[3].a: ..."), relative
// vm paths are resolved against `baseDir`.
Result<Scene> parseScene(const std::string& text, const std::string& name, const std::filesystem::path& baseDir);
Result<Scene> loadScene(const std::filesystem::path& path);

// The scene as JSON with the model's active operations (when given) in place of scene.operations.
std::string sceneToJson(const Scene& scene, const Model* model = nullptr);
// One operation as the scene file writes it (a JSON object on one line).
std::string operationToJson(const Operation& op);
// A scene file's text from its head (sceneToJson of a scene without operations) and operations
// (operationToJson each). Fails with a message when the head is not a scene's JSON.
Result<std::string> sceneWithOperations(const std::string& head, const std::vector<std::string>& operations);
// Writes atomically (a temporary file, fsync, a rename, fsync of the folder): a full disk or a power
// cut leaves the old file or the new one, never half of one.
// (writeFileAtomically(), util/durable_file.h.)
Status saveScene(const Scene& scene, const Model* model, const std::filesystem::path& path);

const char* deformationName(Deformation d);

}  // namespace emboss
