// The host's steal time, for the bench's tables.
#include "bench/host_cpu.h"

#include <gtest/gtest.h>
#include <unistd.h>

namespace emboss {
namespace {

TEST(HostCpu, ReadsTheCpuLineOfProcStat) {
  // proc(5): user nice system idle iowait irq softirq steal guest guest_nice.
  const auto t = parseHostCpuTimes("cpu  100 5 20 9000 7 3 2 40 11 0\ncpu0 50 2 10 4500 3 1 1 20 5 0\nintr 1 2\n");
  ASSERT_TRUE(t.has_value());
  EXPECT_EQ(t->steal, 40u);
  EXPECT_EQ(t->busy, 130u);  // user + nice + system + irq + softirq (guest is in user already)
}

TEST(HostCpu, AMalformedProcStatGivesNothing) {
  EXPECT_FALSE(parseHostCpuTimes("").has_value());
  EXPECT_FALSE(parseHostCpuTimes("cpu0 1 2 3 4 5 6 7 8\n").has_value());  // no machine-wide line
  EXPECT_FALSE(parseHostCpuTimes("cpu  1 2 3 4 5\n").has_value());        // too few fields for steal
  EXPECT_FALSE(parseHostCpuTimes("cpu  a b c d e f g h\n").has_value());
}

TEST(HostCpu, TheSentenceGivesStealAsAShareOfTheTimeTheMachineWanted) {
  const double tick = static_cast<double>(sysconf(_SC_CLK_TCK));
  const HostCpuTimes before{100, 1000}, after{100 + static_cast<std::uint64_t>(tick), 1000 + 3 * static_cast<std::uint64_t>(tick)};
  // One second stolen while the machine worked three: a quarter of the four it wanted.
  EXPECT_EQ(stealSentence(before, after).substr(0, 37), "steal 25.0 % of its CPU time (1.0 s: ");
  EXPECT_EQ(stealSentence(before, before).substr(0, 34), "steal 0.0 % of its CPU time (0.0 s");
  EXPECT_TRUE(stealSentence(std::nullopt, after).empty());
  EXPECT_TRUE(stealSentence(after, before).empty());  // counters that went back: no figure
}

TEST(HostCpu, NoStealSinceBootIsSaidAsSuch) {
  // A hypervisor that never reports steal reads as a quiet host: the sentence says it cannot tell.
  const HostCpuTimes before{0, 1000}, after{0, 5000};
  const std::string s = stealSentence(before, after);
  EXPECT_EQ(s.substr(0, 30), "steal 0.0 % of its CPU time (n");
  EXPECT_NE(s.find("none counted since this machine booted"), std::string::npos) << s;
  // Steal counted before the run but none during it: a quiet host, said plainly.
  EXPECT_EQ(stealSentence(HostCpuTimes{7, 1000}, HostCpuTimes{7, 5000}).find("booted"), std::string::npos);
}

TEST(HostCpu, ThisMachinesCountersOnlyGrow) {
  const auto a = readHostCpuTimes();
  if (!a) GTEST_SKIP() << "no /proc/stat here";
  volatile double x = 0;
  for (int i = 0; i < 2000000; ++i) x = x + 1.0;
  const auto b = readHostCpuTimes();
  ASSERT_TRUE(b.has_value());
  EXPECT_GE(b->steal, a->steal);
  EXPECT_GE(b->busy, a->busy);
  EXPECT_FALSE(stealSentence(a, b).empty());
}

}  // namespace
}  // namespace emboss
