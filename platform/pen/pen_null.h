// The null pen: a PenSource that never yields a sample.
#pragma once

#include "devices/pen.h"

namespace emboss {

class NullPen final : public PenSource {
 public:
  std::string name() const override;
  bool poll(std::vector<PenSample>& out) override;
};

}  // namespace emboss
