// Where the pen's screen ray meets the metal: ray picking by evaluating the model along the camera ray.
#pragma once

#include <optional>
#include <vector>

#include <glm/glm.hpp>

#include "frep/model.h"
#include "render/camera.h"

namespace emboss {

// A screen rectangle in pixels (origin top left); doubles, unlike render's Rect.
struct ScreenBox {
  double x = 0, y = 0, w = 0, h = 0;
};

// The first point where the ray through screen position (sx, sy) (pixels) enters the model
// (f crosses from < 0 to >= 0), found by marching in steps of a fraction of the sheet's thickness
// and bisecting; nullopt when the ray misses. Each evaluation reads only the operations whose
// support holds its point (or meets its box), and stretches of the march that interval arithmetic
// proves to lie outside the model are skipped (`skipOutside`; off, every sample is evaluated: the
// same point, some fifteen times slower on an attract piece). Thread-safe (const).
std::optional<glm::dvec3> pickSurface(const Model& model, const Camera& camera, double sx, double sy,
                                      bool skipOutside = true);

// The radius in pixels of a circle of `radiusMm` lying around `p` (for the footprint ring).
double projectedRadius(const Camera& camera, const glm::dvec3& p, double radiusMm);

// The bounding rectangle of the workpiece's front face on the screen.
ScreenBox sheetOnScreen(const Camera& camera, const Box3& workpieceBounds);

// Where the tablet's active area (aspect = width / height) lands: the sheet's rectangle grown to
// that aspect around its centre, plus a margin so the edges are easy to reach. Absolute mapping.
ScreenBox tabletArea(const ScreenBox& sheet, double aspect, double margin = 0.04);

}  // namespace emboss
