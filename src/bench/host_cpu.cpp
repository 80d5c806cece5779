// How busy the host was while a benchmark ran (see host_cpu.h).
#include "bench/host_cpu.h"

#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <sstream>

namespace emboss {

std::optional<HostCpuTimes> parseHostCpuTimes(const std::string& procStat) {
  // "cpu  user nice system idle iowait irq softirq steal guest guest_nice" (proc(5)); guest time
  // is already counted in user.
  std::istringstream in(procStat);
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("cpu ", 0) != 0) continue;
    std::istringstream f(line.substr(4));
    std::uint64_t v[8] = {};
    for (auto& x : v)
      if (!(f >> x)) return std::nullopt;
    return HostCpuTimes{v[7], v[0] + v[1] + v[2] + v[5] + v[6]};
  }
  return std::nullopt;
}

std::optional<HostCpuTimes> readHostCpuTimes() {
  std::ifstream f("/proc/stat");
  if (!f) return std::nullopt;
  std::stringstream text;
  text << f.rdbuf();
  return parseHostCpuTimes(text.str());
}

std::string stealSentence(const std::optional<HostCpuTimes>& before, const std::optional<HostCpuTimes>& after) {
  if (!before || !after || after->steal < before->steal || after->busy < before->busy) return {};
  const double steal = static_cast<double>(after->steal - before->steal);
  const double busy = static_cast<double>(after->busy - before->busy);
  const double ticks = static_cast<double>(sysconf(_SC_CLK_TCK) > 0 ? sysconf(_SC_CLK_TCK) : 100);
  char detail[160];
  if (after->steal == 0)
    // Not a tick since the machine booted: a quiet host, or a hypervisor that does not report
    // steal time (some do not), which would then not show a busy host either.
    std::snprintf(detail, sizeof detail,
                  "none counted since this machine booted: a quiet host, or one that does not report steal time, so a "
                  "busy host would not show here");
  else
    std::snprintf(detail, sizeof detail,
                  "%.1f s: the host's other guests held the cores; wall times are longer by about that share", steal / ticks);
  char b[240];
  std::snprintf(b, sizeof b, "steal %.1f %% of its CPU time (%s)", steal + busy > 0 ? 100.0 * steal / (steal + busy) : 0.0,
                detail);
  return b;
}

}  // namespace emboss
