// How busy the host was while a benchmark ran: on a virtual machine, the time the hypervisor gave
// this machine's cores to other guests ("steal", /proc/stat). A wall time measured while a tenth
// of the cores' time was stolen is that much slower than the same code on a quiet host.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

namespace emboss {

// The machine's CPU time so far, in clock ticks, summed over its cores (/proc/stat's "cpu" line).
struct HostCpuTimes {
  std::uint64_t steal = 0;  // taken by the hypervisor for other guests while this machine wanted to run
  std::uint64_t busy = 0;   // user, nice, system, irq and softirq: this machine's own work
};

// From the text of /proc/stat; nothing when its "cpu" line is missing or malformed.
std::optional<HostCpuTimes> parseHostCpuTimes(const std::string& procStat);
// This machine's, now (nothing where /proc/stat cannot be read: not Linux).
std::optional<HostCpuTimes> readHostCpuTimes();

// A sentence on the host between two readings, for a benchmark's table: the steal time as a share
// of the time this machine worked or waited for a core, e.g. "steal 8.4 % of its CPU time (1.3 s:
// the host's other guests held the cores; wall times are longer by about that share)". When no
// steal has been counted since the machine booted, it says so: a hypervisor that does not report
// steal time reads as a quiet host. Empty when either reading is missing.
std::string stealSentence(const std::optional<HostCpuTimes>& before, const std::optional<HostCpuTimes>& after);

}  // namespace emboss
