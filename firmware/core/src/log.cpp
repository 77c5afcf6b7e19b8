#include "handscan/core/log.hpp"

#include <spdlog/pattern_formatter.h>
#include <spdlog/sinks/stdout_color_sinks.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <memory>

namespace handscan {
namespace {

// syslog priorities (sd-daemon.h: SD_ERR "<3>" ... SD_DEBUG "<7>").
class JournalPriorityFlag final : public spdlog::custom_flag_formatter {
public:
    void format(const spdlog::details::log_msg& msg, const std::tm&,
                spdlog::memory_buf_t& dest) override {
        int prio = 6;
        switch (msg.level) {
            case spdlog::level::trace:
            case spdlog::level::debug:
                prio = 7;
                break;
            case spdlog::level::info:
                prio = 6;
                break;
            case spdlog::level::warn:
                prio = 4;
                break;
            case spdlog::level::err:
                prio = 3;
                break;
            case spdlog::level::critical:
                prio = 2;
                break;
            default:
                prio = 6;
        }
        const char text[4] = {'<', static_cast<char>('0' + prio), '>', '\0'};
        dest.append(text, text + 3);
    }
    std::unique_ptr<custom_flag_formatter> clone() const override {
        return std::make_unique<JournalPriorityFlag>();
    }
};

}  // namespace

bool stderrIsTerminal() { return isatty(STDERR_FILENO) == 1; }

void initLogging(const std::string& process_name, int verbosity) {
    auto sink = std::make_shared<spdlog::sinks::stderr_color_sink_mt>();
    auto logger = std::make_shared<spdlog::logger>(process_name, sink);
    const bool under_journal = std::getenv("JOURNAL_STREAM") != nullptr;
    auto formatter = std::make_unique<spdlog::pattern_formatter>();
    if (under_journal) {
        formatter->add_flag<JournalPriorityFlag>('*').set_pattern("%*%v");
    } else {
        formatter->set_pattern("%H:%M:%S.%e %^%l%$ %v");
    }
    logger->set_formatter(std::move(formatter));
    spdlog::level::level_enum level = spdlog::level::info;
    if (verbosity < 0) level = spdlog::level::warn;
    if (verbosity == 1) level = spdlog::level::debug;
    if (verbosity >= 2) level = spdlog::level::trace;
    logger->set_level(level);
    spdlog::set_default_logger(logger);
}

Progress::Progress(std::string what, double total)
    : what_(std::move(what)), total_(std::max(total, 1e-9)), tty_(stderrIsTerminal()) {}

Progress::~Progress() { finish(); }

void Progress::update(double done) {
    const int percent = static_cast<int>(std::clamp(done / total_, 0.0, 1.0) * 100.0);
    if (percent == last_percent_) return;
    if (tty_) {
        std::fprintf(stderr, "\r%s: %3d%%", what_.c_str(), percent);
        std::fflush(stderr);
    } else if (percent / 10 != last_percent_ / 10) {
        log().info("{}: {}%", what_, percent);
    }
    last_percent_ = percent;
}

void Progress::finish() {
    if (finished_) return;
    finished_ = true;
    if (tty_ && last_percent_ >= 0) std::fprintf(stderr, "\r%s: done\n", what_.c_str());
}

}  // namespace handscan
