// File-name stamps from the local time.
#include "util/file_stamp.h"

#include <ctime>

namespace emboss {

std::string fileStamp() {
  const std::time_t t = std::time(nullptr);
  std::tm tm{};
  localtime_r(&t, &tm);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y%m%d-%H%M%S", &tm);
  return buf;
}

}  // namespace emboss
