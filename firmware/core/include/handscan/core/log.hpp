// One logging facade for every process. Under systemd (JOURNAL_STREAM set) lines carry the
// journal's "<N>" priority prefix so journald files them at the right level; on a terminal they
// are coloured and time-stamped. Everything else calls handscan::log().
#pragma once

#include <spdlog/spdlog.h>

#include <string>

namespace handscan {

// Sets up the default logger once per process. `verbosity`: 0 = info, 1 = debug, 2 = trace,
// -1 = warnings only.
void initLogging(const std::string& process_name, int verbosity = 0);

// True when stderr is a terminal (progress bars, colours).
bool stderrIsTerminal();

// The shared logger.
inline spdlog::logger& log() { return *spdlog::default_logger_raw(); }

// A progress indicator for long operations: a single updating line on a terminal, a log line
// every 10 % otherwise (so the journal is not flooded).
class Progress {
public:
    Progress(std::string what, double total);
    ~Progress();
    Progress(const Progress&) = delete;
    Progress& operator=(const Progress&) = delete;
    void update(double done);
    void finish();

private:
    std::string what_;
    double total_;
    int last_percent_ = -1;
    bool tty_;
    bool finished_ = false;
};

}  // namespace handscan
