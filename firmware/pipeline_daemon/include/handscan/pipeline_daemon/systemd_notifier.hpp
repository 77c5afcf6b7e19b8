// The daemon's side of systemd's Type=notify protocol (sd_notify): READY=1 once the devices have
// been opened, STATUS= lines for `systemctl status`, WATCHDOG=1 while the main loop and the
// pipeline thread both make progress, STOPPING=1 on the way out. Without $NOTIFY_SOCKET (not
// started by systemd) every call is a no-op. Only this file's implementation includes sd-daemon.
#pragma once

#include <string>

#include "handscan/core/time.hpp"

namespace handscan::pipeline_daemon {

class SystemdNotifier {
public:
    SystemdNotifier();
    void ready(const std::string& status);
    void status(const std::string& status);  // sent only when it changed
    // Feeds the watchdog at half its period (WatchdogSec / 2), or once a second without one.
    void watchdog(TimeNs now);
    void stopping(const std::string& status);

private:
    void send(const std::string& message);

    TimeNs watchdog_interval_ = kNsPerSec;
    TimeNs last_watchdog_ = 0;
    std::string last_status_;
};

}  // namespace handscan::pipeline_daemon
