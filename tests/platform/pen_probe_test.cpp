// Tests for tablet probing: always-safe checks, and *Hardware* suites that need a tablet plugged in.
#include <gtest/gtest.h>

#include <poll.h>

#include "pen/pen_evdev.h"
#include "pen/pen_probe.h"
#include "pen/pen_replay.h"
#include "pen/usb_uclogic.h"

namespace emboss {
namespace {

bool anyUsable(const std::vector<DeviceReport>& reports) {
  for (const auto& r : reports) {
    if (r.usable) return true;
  }
  return false;
}

TEST(PenProbe, ReportsAreExplainedAndOpeningFailsClearlyWithoutATablet) {
  const auto reports = probeTablets();
  for (const auto& r : reports) {
    EXPECT_TRUE(r.backend == "evdev" || r.backend == "hidraw") << r.backend;
    EXPECT_FALSE(r.detail.empty()) << r.path;
  }
  if (anyUsable(reports)) GTEST_SKIP() << "a tablet is connected; see the PenProbeHardware suite";
  const auto pen = openFirstTablet();
  ASSERT_FALSE(pen);
  EXPECT_NE(pen.error().find("no tablet found"), std::string::npos) << pen.error();
}

TEST(PenProbe, EvdevOpenFailsClearlyOnAMissingNode) {
  const auto pen = EvdevPen::open("/dev/input/event-none");
  ASSERT_FALSE(pen);
  EXPECT_NE(pen.error().find("/dev/input/event-none"), std::string::npos) << pen.error();
}

TEST(PenProbe, UclogicHandshakeFailsClearlyWithoutTheDevice) {
  const auto p = uclogicHandshake(0x256c, 0x7fff);
  ASSERT_FALSE(p);
  EXPECT_FALSE(p.error().empty());
  const auto notUclogic = uclogicHandshake(0x046d, 0xc077);
  ASSERT_FALSE(notUclogic);
  EXPECT_NE(notUclogic.error().find("not a UC-Logic vendor"), std::string::npos) << notUclogic.error();
}

// Needs a tablet: draw on it within 10 s of the start.
TEST(PenProbeHardware, FirstTabletGivesNormalisedSamples) {
  if (!anyUsable(probeTablets())) GTEST_SKIP() << "no tablet connected";
  auto pen = openFirstTablet();
  ASSERT_TRUE(pen) << pen.error();
  std::vector<PenSample> out;
  const double start = monotonicSeconds();
  while (out.empty() && monotonicSeconds() - start < 10.0) {
    if ((*pen)->fd() >= 0) {
      pollfd p{(*pen)->fd(), POLLIN, 0};
      ::poll(&p, 1, 100);
    }
    ASSERT_TRUE((*pen)->poll(out)) << "the tablet went away";
  }
  if (out.empty()) GTEST_SKIP() << "nobody touched the tablet within 10 s";
  for (const auto& s : out) {
    EXPECT_GE(s.x, 0.0);
    EXPECT_LE(s.x, 1.0);
    EXPECT_GE(s.y, 0.0);
    EXPECT_LE(s.y, 1.0);
    EXPECT_GE(s.pressure, 0.0);
    EXPECT_LE(s.pressure, 1.0);
  }
}

TEST(PenProbeHardware, UclogicHandshakeOnConnectedTablets) {
  const auto devices = enumerateUclogicUsb();
  if (!devices || devices->empty()) GTEST_SKIP() << "no UC-Logic tablet on USB";
  for (const auto& d : *devices) {
    const auto p = uclogicHandshake(d);
    if (!p) {
      ADD_FAILURE() << d.describe() << ": " << p.error();
      continue;
    }
    EXPECT_GT(p->xMax, 0);
    EXPECT_GT(p->pressureMax, 0);
  }
}

}  // namespace
}  // namespace emboss
