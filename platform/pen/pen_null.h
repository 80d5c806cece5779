// The null pen: a PenSource that never yields a sample.
#pragma once

#include <limits>

#include "devices/pen.h"

namespace emboss {

class NullPen final : public PenSource {
 public:
  std::string name() const override;
  bool poll(std::vector<PenSample>& out) override;
  double pollWithin() const override { return std::numeric_limits<double>::infinity(); }  // nothing ever comes
};

}  // namespace emboss
