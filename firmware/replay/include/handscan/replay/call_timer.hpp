// Per-module cost of calls (replay's stats.json): every call's duration is kept so the mean,
// median, 99th percentile and maximum are exact.
#pragma once

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace handscan::replay {

struct CallStats {
    std::uint64_t calls = 0;
    double mean_us = 0, p50_us = 0, p99_us = 0, max_us = 0, total_ms = 0;
};

class CallTimer {
public:
    void add(const std::string& module, double us) { samples_[module].push_back(us); }

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
        for (auto [name, v] : samples_) {
            if (v.empty()) continue;
            std::sort(v.begin(), v.end());
            CallStats s;
            s.calls = v.size();
            double sum = 0;
            for (double x : v) sum += x;
            s.mean_us = sum / static_cast<double>(v.size());
            s.p50_us = v[v.size() / 2];
            s.p99_us = v[std::min(v.size() - 1, static_cast<std::size_t>(0.99 * static_cast<double>(v.size())))];
            s.max_us = v.back();
            s.total_ms = sum * 1e-3;
            out[name] = s;
        }
        return out;
    }

private:
    static double elapsedUs(std::chrono::steady_clock::time_point t0) {
        return std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - t0).count();
    }
    std::map<std::string, std::vector<double>> samples_;
};

}  // namespace handscan::replay
