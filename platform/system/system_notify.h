// Telling the service manager how the kiosk is doing: systemd's sd_notify (ready, watchdog, status),
// with a null twin when the kiosk does not run under systemd.
#pragma once

#include <memory>
#include <string>

namespace emboss {

class SystemNotifier {
 public:
  virtual ~SystemNotifier() = default;
  virtual std::string name() const = 0;
  // Start-up is done (Type=notify units are "active" from here on).
  virtual void ready(const std::string& status) = 0;
  // The main loop is alive. Rate-limited here to half the watchdog interval: call it every turn.
  virtual void alive(double nowSeconds) = 0;
  virtual void status(const std::string& text) = 0;
  virtual void stopping() = 0;
  // Seconds between watchdog pings systemd expects (0: no watchdog).
  virtual double watchdogSeconds() const = 0;
};

// The systemd notifier when $NOTIFY_SOCKET is set, else the null one (nothing is sent).
std::unique_ptr<SystemNotifier> createSystemNotifier();

}  // namespace emboss
