// POV-Ray 3.7 export: the model's own function as an isosurface, with the same camera, light and metal.
#pragma once

#include <string>

#include "frep/model.h"
#include "scene/scene.h"
#include "util/result.h"

namespace emboss {

struct PovExportOptions {
  int width = 1280;   // for the camera's aspect ratio
  int height = 800;
};

// The POV-Ray scene text. It #declares Emboss_Function(x, y, z) (the model's value, >= 0 inside,
// in the scene's own right-handed coordinates) and Emboss_Object (the isosurface, placed in POV's
// left-handed space by mirroring z); unless Emboss_Declare_Only is declared before the file is
// included, it also places the camera, the lights and the object. Every kernel is written from
// the same definitions the evaluator uses (docs/kernels.md).
Result<std::string> exportPov(const Scene& scene, const Model& model, const PovExportOptions& options);

}  // namespace emboss
