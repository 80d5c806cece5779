#include "platform_util.h"

#include <time.h>

#include <cstdio>
#include <mutex>
#include <set>

namespace emboss {

void logOnce(const std::string& message) {
  static std::mutex mutex;
  static std::set<std::string> logged;
  std::lock_guard<std::mutex> lock(mutex);
  if (logged.insert(message).second) std::fprintf(stderr, "emboss: %s\n", message.c_str());
}

double monotonicSeconds() {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<double>(ts.tv_sec) + static_cast<double>(ts.tv_nsec) * 1e-9;
}

}  // namespace emboss
