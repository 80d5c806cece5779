// The front face as a 16-bit greyscale height map: the input of relief CAD tools and CNC mills.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "frep/model.h"
#include "util/result.h"

namespace emboss {

struct HeightMapOptions {
  double pixel = 0.0;    // mm per pixel; 0: 0.1 mm, coarser when the longer side would pass maxSide
  int maxSide = 4096;
  int threads = 0;
  std::function<void(double)> progress;  // fraction done, never concurrently
};

// Row 0 is the far edge of the plate (largest y), as a picture of the front face is seen. Each
// value is the height of the front face (the highest point of metal) over the pixel's centre:
// 0 where there is no metal, else 1 + round((z - zMin) / (zMax - zMin) * 65534).
struct HeightMap {
  int width = 0, height = 0;
  double pixel = 0.0;        // mm
  double x0 = 0.0, y1 = 0.0;  // the centre of pixel (0, 0): left, top
  double zMin = 0.0, zMax = 0.0;
  std::vector<std::uint16_t> values;  // row-major
  // mm of a value (v >= 1).
  double z(std::uint16_t v) const { return zMin + (v - 1) * (zMax - zMin) / 65534.0; }
};

// Finds the front face by interval arithmetic down each pixel's column and bisection at the top.
Result<HeightMap> heightMap(const Model& model, const HeightMapOptions& options);

// The PNG's bytes: 16-bit greyscale, the scale in its text chunks (emboss:pixel_mm, emboss:z_min_mm,
// emboss:z_max_mm, emboss:origin_mm, and a sentence in Comment) and in pHYs (pixels per metre).
Result<std::string> heightMapPng(const HeightMap& map, const std::string& title);

}  // namespace emboss
