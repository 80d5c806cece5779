// The take-home exports behind `emboss export`: STL, 3MF, the height map and the postcard.
#pragma once

#include <string>

#include "export/postcard.h"
#include "frep/model.h"
#include "scene/scene.h"
#include "util/result.h"

namespace emboss::cli {

struct TakeHomeOptions {
  std::string format;       // stl, 3mf, heightmap, postcard
  double resolution = 0.0;  // mesh cell or height map pixel, mm; 0: automatic
  double maxError = 0.01;   // mesh decimation, mm; 0: none
  int threads = 0;
  bool progressBar = true;  // on stderr, only when it is a terminal
  TextPainter* text = nullptr;  // postcard: the caption's painter (none: no words)
};

// Writes `out` atomically; `summary` gets one line of figures (triangles, distances, time).
Status writeTakeHome(const Scene& scene, const Model& model, const TakeHomeOptions& options, const std::string& out,
                     std::string* summary = nullptr);

}  // namespace emboss::cli
