// sd_notify for the kiosk's service (READY=1, WATCHDOG=1, STATUS=, STOPPING=1), or nothing.
#include "system/system_notify.h"

#include <systemd/sd-daemon.h>

#include <cstdlib>

namespace emboss {

namespace {

class SystemdNotifier final : public SystemNotifier {
 public:
  SystemdNotifier() {
    uint64_t usec = 0;
    if (sd_watchdog_enabled(0, &usec) > 0) watchdog_ = static_cast<double>(usec) * 1e-6;
  }
  std::string name() const override { return "systemd"; }
  void ready(const std::string& status) override { sd_notifyf(0, "READY=1\nSTATUS=%s", status.c_str()); }
  void alive(double now) override {
    if (watchdog_ <= 0 || now - last_ < watchdog_ / 2) return;
    last_ = now;
    sd_notify(0, "WATCHDOG=1");
  }
  void status(const std::string& text) override { sd_notifyf(0, "STATUS=%s", text.c_str()); }
  void stopping() override { sd_notify(0, "STOPPING=1"); }
  double watchdogSeconds() const override { return watchdog_; }

 private:
  double watchdog_ = 0;
  double last_ = -1e9;
};

class NullNotifier final : public SystemNotifier {
 public:
  std::string name() const override { return "none (not under systemd)"; }
  void ready(const std::string&) override {}
  void alive(double) override {}
  void status(const std::string&) override {}
  void stopping() override {}
  double watchdogSeconds() const override { return 0; }
};

}  // namespace

std::unique_ptr<SystemNotifier> createSystemNotifier() {
  const char* socket = std::getenv("NOTIFY_SOCKET");
  if (socket && *socket) return std::make_unique<SystemdNotifier>();
  return std::make_unique<NullNotifier>();
}

}  // namespace emboss
