// 3MF (the 3D Manufacturing Format) through lib3mf: the closed mesh in millimetres, with its title.
#pragma once

#include <string>

#include "export/mesh.h"
#include "util/result.h"

namespace emboss {

struct ThreeMfInfo {
  std::string title;        // the object's name and the model's Title metadata
  std::string description;  // the Description metadata
};

// Writes `path` (lib3mf writes the zip itself; the caller renames a temporary file into place).
Status write3mf(const TriangleMesh& mesh, const ThreeMfInfo& info, const std::string& path);

// Reads a 3MF back (for checks): its first mesh object's triangle and vertex counts, and whether
// lib3mf finds it manifold and oriented.
struct ThreeMfSummary {
  unsigned long triangles = 0, vertices = 0;
  bool manifoldAndOriented = false;
  std::string unit;
};
Result<ThreeMfSummary> read3mfSummary(const std::string& path);

}  // namespace emboss
