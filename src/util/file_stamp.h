// A stamp for file names from the local time now: 20250314-153012.
#pragma once

#include <string>

namespace emboss {

std::string fileStamp();

}  // namespace emboss
