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
};

}  // namespace emboss
