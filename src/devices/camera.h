// The camera: stills of a drawing on paper, to map onto the plate as a guide.
#pragma once

#include <string>

#include "render/image.h"
#include "util/result.h"

namespace emboss {

class CameraSource {
 public:
  virtual ~CameraSource() = default;
  virtual std::string name() const = 0;
  // One still, RGBA. Fails with a message when the camera is gone or times out.
  virtual Result<Image> capture() = 0;
  // Whether the camera is still there: cheap, never blocks, and false once it is known to be gone
  // (unplugged, or lost by a failed capture). The kiosk drops a camera that is not and looks for
  // one again. Not to be called while capture() runs on another thread.
  virtual bool present() { return true; }
};

}  // namespace emboss
