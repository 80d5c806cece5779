// Capture drawing: a photo of a drawing on paper to a guide image on the plate and traced contours.
#pragma once

#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "capture/homography.h"
#include "frep/operation.h"
#include "render/image.h"
#include "util/result.h"

namespace emboss {

struct CaptureOptions {
  // The paper's long side over its short side (A-series: sqrt 2); 0 takes it from the photo (which
  // perspective skews a little). The photo's top stays the drawing's top.
  double paperAspect = std::sqrt(2.0);
  double marginMm = 5.0;        // the paper maps onto the plate inset by this much, aspect kept, centred
  double borderFrac = 0.025;    // ink this close to the paper's edge (of its short side) is ignored: shadows
  double guidePxPerMm = 4.0;    // the guide image's resolution
  double simplifyMm = 0.25;      // Ramer-Douglas-Peucker tolerance, on the plate
  double minStrokeMm = 2.0;     // shorter strokes (specks, dots) are dropped
  std::string tracer = "Tracer";  // a tracer of toolCatalogue()
  std::string metal = "copper";
  double pressure = 0.5;        // 0..1, as from the pen
};

// Where things are: photo pixels, the rectified paper's pixels and the plate's millimetres (x right,
// y up, origin at the plate's centre, as the Plate workpiece; gray.h's pixel convention).
struct DrawingMapping {
  Homography photoToPaper;        // photo pixels to paper pixels
  Homography paperToPhoto;
  int paperWidth = 0, paperHeight = 0;  // the rectified sheet, pixels
  double mmPerPaperPx = 1.0;      // on the plate
  double plateW = 0, plateH = 0;  // mm
  double guidePxPerMm = 4.0;

  Vec2 paperToPlate(Vec2 paperPx) const;
  Vec2 plateToPaper(Vec2 mm) const;
  Vec2 photoToPlate(Vec2 photoPx) const { return paperToPlate(photoToPaper.apply(photoPx)); }
  Vec2 plateToPhoto(Vec2 mm) const { return paperToPhoto.apply(plateToPaper(mm)); }
  // Guide pixels: row 0 at the plate's top edge (y = +plateH / 2).
  Vec2 plateToGuide(Vec2 mm) const { return {(mm.x + plateW / 2) * guidePxPerMm, (plateH / 2 - mm.y) * guidePxPerMm}; }
};

struct CaptureResult {
  std::array<Vec2, 4> corners;  // the sheet in the photo: top-left, top-right, bottom-right, bottom-left
  DrawingMapping mapping;
  Image paper;  // the sheet rectified, its light evened out (white paper, dark ink), paper pixels
  Image guide;  // the plate, guidePxPerMm: ink dark and opaque, paper and outside transparent
  std::vector<std::vector<Vec2>> polylines;  // the strokes in plate mm; a closed one repeats its first point
  std::vector<Operation> operations;         // the strokes as Trace operations (side Front), at most kTraceSegment mm each
  double strokeWidthMm = 0.0;   // the ink's mean width, on the plate
};

// The whole pipeline: findSheet, rectification by the homography of its corners, ink by an adaptive
// threshold, the guide, Zhang-Suen skeleton, polylines, simplification, plate millimetres and trace
// operations. plateW and plateH are the plate's full width and height (mm). Fails with "no sheet of
// paper found: ..." or "no drawing found on the sheet: ...". Pure and thread-safe; about 0.1 to
// 0.5 s for a 1280x960 photo, so call it off the render thread.
Result<CaptureResult> captureDrawing(const Image& photo, double plateW, double plateH, const CaptureOptions& options = {});

// The same from known corners (top-left, top-right, bottom-right, bottom-left; photo pixels), e.g.
// after the staff corrected them by hand.
Result<CaptureResult> captureDrawingInSheet(const Image& photo, const std::array<Vec2, 4>& corners, double plateW, double plateH,
                                            const CaptureOptions& options = {});

// Splits a polyline (plate mm) into Trace operations of at most kTraceSegment mm, consecutive pieces
// sharing their joint, with the named tracer of toolCatalogue() on the named metal.
Result<std::vector<Operation>> traceOperations(const std::vector<std::vector<Vec2>>& polylines, const CaptureOptions& options);

}  // namespace emboss
