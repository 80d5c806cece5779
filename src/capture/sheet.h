// Finding the sheet of paper in a photo: the largest bright quadrilateral, its corners to a pixel or better.
#pragma once

#include <array>

#include "capture/gray.h"
#include "frep/operation.h"
#include "render/image.h"
#include "util/result.h"

namespace emboss {

struct Sheet {
  std::array<Vec2, 4> corners;  // top-left, top-right, bottom-right, bottom-left; photo pixels (gray.h)
  double contrast = 0.0;        // median log brightness step across the edges (0.5: 65 % brighter inside)
  double edgeSupport = 0.0;     // the fraction of edge samples that show a clear bright-inside step
};

// Finds the sheet: candidate regions from several brightness thresholds and from the regions that
// edges of the log image enclose (a step in log brightness does not depend on the light, so uneven
// light does not hide the sheet's edge), each fitted with its largest inscribed quadrilateral and
// scored by how well it fills it and how clear its edges are; then each side is refined to the
// photo's full resolution by a robust line fit to the edge profile. Fails with "no sheet of paper
// found: ..." when nothing looks like a sheet with all four corners in view.
Result<Sheet> findSheet(const GrayImage& photo);
Result<Sheet> findSheet(const Image& photo);

}  // namespace emboss
