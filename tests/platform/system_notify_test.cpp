// sd_notify as systemd sees it: a datagram socket standing in for the service manager receives
// READY, STATUS, rate-limited WATCHDOG pings and STOPPING; without NOTIFY_SOCKET nothing is sent.
#include <gtest/gtest.h>

#include <poll.h>
#include <stdlib.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <string>
#include <vector>

#include "system/system_notify.h"
#include "test_support.h"

namespace emboss {
namespace {

// Every datagram waiting on fd.
std::vector<std::string> receive(int fd) {
  std::vector<std::string> out;
  char buf[4096];
  pollfd p{fd, POLLIN, 0};
  while (::poll(&p, 1, 200) > 0) {
    const ssize_t n = ::recv(fd, buf, sizeof buf, 0);
    if (n <= 0) break;
    out.emplace_back(buf, static_cast<size_t>(n));
  }
  return out;
}

TEST(SystemNotify, ReadyWatchdogStatusAndStoppingReachTheServiceManager) {
  const auto dir = test::scratchDir("system-notify");
  const std::string path = (dir / "notify.sock").string();
  const int fd = ::socket(AF_UNIX, SOCK_DGRAM | SOCK_CLOEXEC, 0);
  ASSERT_GE(fd, 0);
  sockaddr_un addr{};
  addr.sun_family = AF_UNIX;
  ASSERT_LT(path.size(), sizeof addr.sun_path);
  std::copy(path.begin(), path.end(), addr.sun_path);
  ::unlink(path.c_str());
  ASSERT_EQ(::bind(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr), 0);

  ::setenv("NOTIFY_SOCKET", path.c_str(), 1);
  ::setenv("WATCHDOG_USEC", "2000000", 1);  // 2 s: pings every 1 s at most
  ::unsetenv("WATCHDOG_PID");
  auto n = createSystemNotifier();
  EXPECT_EQ(n->name(), "systemd");
  EXPECT_DOUBLE_EQ(n->watchdogSeconds(), 2.0);
  n->ready("attract mode");
  for (double t = 0; t < 3.05; t += 0.1) n->alive(100.0 + t);  // the main loop, 3 s of it
  n->status("waiting for a screen");
  n->stopping();
  const auto got = receive(fd);
  ::unsetenv("NOTIFY_SOCKET");
  ::unsetenv("WATCHDOG_USEC");
  ::close(fd);

  ASSERT_FALSE(got.empty());
  EXPECT_EQ(got.front(), "READY=1\nSTATUS=attract mode");
  int pings = 0;
  for (const auto& m : got) pings += m == "WATCHDOG=1";
  EXPECT_EQ(pings, 4);  // at 0, 1, 2 and 3 s: every half interval, not every loop turn
  EXPECT_EQ(got[got.size() - 2], "STATUS=waiting for a screen");
  EXPECT_EQ(got.back(), "STOPPING=1");

  // Not under systemd: the null notifier.
  auto none = createSystemNotifier();
  EXPECT_EQ(none->name(), "none (not under systemd)");
  EXPECT_EQ(none->watchdogSeconds(), 0.0);
}

}  // namespace
}  // namespace emboss
