// The studio export: the lighting, the camera and the metal of a scene for a path tracer, so that
// a reference picture of the same scene can be rendered elsewhere (tests/reference/).
#pragma once

#include <string>

#include "frep/model.h"
#include "scene/scene.h"
#include "util/result.h"

namespace emboss {

// Writes `hdrPath`: the studio environment (studioEnvironment()) as a Radiance RGBE picture,
// equirectangular as Blender maps a world texture: pixel column u and row v (v = 0 at the top) look
// along d = (cos t cos p, cos t sin p, sin t), p = (0.5 - (u + 0.5) / W) 2 pi, t = (0.5 - (v + 0.5) / H) pi,
// in the scene's own axes. And `jsonPath`: the camera, the metal's optical constants and roughness,
// the tinge and the tone curve this renderer applies, with the picture's file name.
Status writeStudio(const Scene& scene, const std::string& hdrPath, const std::string& jsonPath, int width = 2048);

}  // namespace emboss
