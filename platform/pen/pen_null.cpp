// The null pen: no tablet at all (the kiosk still runs; attract mode and buttons work).
#include "pen/pen_null.h"

namespace emboss {

std::string NullPen::name() const { return "none"; }
bool NullPen::poll(std::vector<PenSample>&) { return true; }

}  // namespace emboss
