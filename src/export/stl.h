// Binary STL: the closed mesh of the sheet, in millimetres, for slicers and mills.
#pragma once

#include <string>

#include "export/mesh.h"

namespace emboss {

// The file's bytes: an 80-byte header (`header`, cut to 80), the triangle count, then per triangle
// its unit normal (from its float vertices, as slicers recompute it), its three vertices and a
// zero attribute, all little-endian.
std::string stlBytes(const TriangleMesh& mesh, const std::string& header);

}  // namespace emboss
