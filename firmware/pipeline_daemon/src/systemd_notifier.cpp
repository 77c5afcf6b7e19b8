#include "handscan/pipeline_daemon/systemd_notifier.hpp"

#include <systemd/sd-daemon.h>

#include "handscan/core/log.hpp"

namespace handscan::pipeline_daemon {

SystemdNotifier::SystemdNotifier() {
    std::uint64_t usec = 0;
    if (sd_watchdog_enabled(0, &usec) > 0 && usec > 0)
        watchdog_interval_ = static_cast<TimeNs>(usec) * 1000 / 2;
}

void SystemdNotifier::send(const std::string& message) {
    if (const int r = sd_notify(0, message.c_str()); r < 0)
        log().warn("sd_notify({}) failed: error {}", message, -r);
}

void SystemdNotifier::ready(const std::string& status) {
    last_status_ = status;
    send("READY=1\nSTATUS=" + status);
}

void SystemdNotifier::status(const std::string& status) {
    if (status == last_status_) return;
    last_status_ = status;
    send("STATUS=" + status);
}

void SystemdNotifier::watchdog(TimeNs now) {
    if (now - last_watchdog_ < watchdog_interval_) return;
    last_watchdog_ = now;
    send("WATCHDOG=1");
}

void SystemdNotifier::stopping(const std::string& status) { send("STOPPING=1\nSTATUS=" + status); }

}  // namespace handscan::pipeline_daemon
