// The null buttons: no GPIO at all (the kiosk still runs; the keyboard stands in for the buttons).
#include "gpio/buttons_null.h"

namespace emboss {

std::string NullButtons::name() const { return "none"; }
bool NullButtons::poll(std::vector<ButtonEvent>&) { return true; }

}  // namespace emboss
