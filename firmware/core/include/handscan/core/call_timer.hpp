// Per-module cost of calls (the pipeline worker's and replay's stats.json). Each module keeps a
// histogram with buckets 0.5 % wide on a log scale (1 ns .. 100 s), not every duration: memory
// stays constant however long the recording (a 30-minute replay times about two million calls).
// Mean, total and maximum are exact; the median and the 99th percentile are within 0.25 % of the
// exact order statistics.
#pragma once

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace handscan {

struct CallStats {
    std::uint64_t calls = 0;
    double mean_us = 0, p50_us = 0, p99_us = 0, max_us = 0, total_ms = 0;
};

class CallTimer {
public:
    void add(const std::string& module, double us) { modules_[module].add(us); }

    // Times `fn` and files it under `module`.
    template <typename Fn>
    auto time(const std::string& module, Fn&& fn) {
        const auto t0 = std::chrono::steady_clock::now();
        if constexpr (std::is_void_v<decltype(fn())>) {
            fn();
            add(module, elapsedUs(t0));
        } else {
            auto r = fn();
            add(module, elapsedUs(t0));
            return r;
        }
    }

    std::map<std::string, CallStats> summary() const {
        std::map<std::string, CallStats> out;
        for (const auto& [name, m] : modules_) {
            if (m.calls == 0) continue;
            CallStats s;
            s.calls = m.calls;
            s.mean_us = m.sum_us / static_cast<double>(m.calls);
            // The same ranks as sorting all durations: element n/2 and element floor(0.99 n).
            s.p50_us = m.quantile(m.calls / 2);
            s.p99_us = m.quantile(std::min(
                m.calls - 1, static_cast<std::uint64_t>(0.99 * static_cast<double>(m.calls))));
            s.max_us = m.max_us;
            s.total_ms = m.sum_us * 1e-3;
            out[name] = s;
        }
        return out;
    }

private:
    static constexpr double kMinUs = 1e-3;
    static constexpr double kRatio = 1.005;
    static constexpr std::size_t kBuckets = 5100;  // kMinUs * kRatio^5100 > 1e8 us

    struct Module {
        std::uint64_t calls = 0;
        double sum_us = 0, min_us = 0, max_us = 0;
        std::vector<std::uint64_t> counts = std::vector<std::uint64_t>(kBuckets, 0);

        static std::size_t bucket(double us) {
            if (!(us > kMinUs)) return 0;
            return std::min(kBuckets - 1,
                            static_cast<std::size_t>(std::log(us / kMinUs) / std::log(kRatio)));
        }
        void add(double us) {
            min_us = calls == 0 ? us : std::min(min_us, us);
            max_us = calls == 0 ? us : std::max(max_us, us);
            ++calls;
            sum_us += us;
            ++counts[bucket(us)];
        }
        // The duration of rank `k` (0-based, ascending): its bucket's geometric centre, within the
        // range seen.
        double quantile(std::uint64_t k) const {
            std::uint64_t seen = 0;
            for (std::size_t b = 0; b < kBuckets; ++b) {
                seen += counts[b];
                if (seen > k) {
                    // The end buckets also hold what lies beyond the range: the extremes seen.
                    if (b == 0) return min_us;
                    if (b == kBuckets - 1) return max_us;
                    const double centre = kMinUs * std::pow(kRatio, static_cast<double>(b) + 0.5);
                    return std::clamp(centre, min_us, max_us);
                }
            }
            return max_us;
        }
    };

    static double elapsedUs(std::chrono::steady_clock::time_point t0) {
        return std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - t0)
            .count();
    }
    std::map<std::string, Module> modules_;
};

}  // namespace handscan
