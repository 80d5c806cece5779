// The null buttons: a ButtonSource that never yields an event.
#pragma once

#include "devices/buttons.h"

namespace emboss {

class NullButtons final : public ButtonSource {
 public:
  std::string name() const override;
  bool poll(std::vector<ButtonEvent>& out) override;
};

}  // namespace emboss
