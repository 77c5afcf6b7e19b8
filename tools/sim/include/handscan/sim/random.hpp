// A small, fully specified random generator (xoshiro256** seeded by splitmix64, Gaussian by the
// Marsaglia polar method), so that a seed gives the same bytes on every platform and standard
// library (std:: distributions are implementation-defined). Each simulated device gets its own
// stream derived from (seed, device), so enabling one sensor never changes another's noise.
#pragma once

#include <cmath>
#include <cstdint>
#include <string_view>

namespace handscan::sim {

class Rng {
public:
    explicit Rng(std::uint64_t seed, std::string_view stream = {}) {
        std::uint64_t x = seed ^ 0x9E3779B97F4A7C15ull;
        for (char c : stream)
            x = (x ^ static_cast<unsigned char>(c)) * 0x100000001B3ull;  // FNV-style mix
        for (auto& s : s_) s = splitmix(x);
    }

    std::uint64_t next() {
        const std::uint64_t result = rotl(s_[1] * 5, 7) * 9;
        const std::uint64_t t = s_[1] << 17;
        s_[2] ^= s_[0];
        s_[3] ^= s_[1];
        s_[1] ^= s_[2];
        s_[0] ^= s_[3];
        s_[2] ^= t;
        s_[3] = rotl(s_[3], 45);
        return result;
    }
    // Uniform in [0, 1).
    double uniform() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }
    double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
    // Uniform integer in [0, n).
    std::uint64_t below(std::uint64_t n) { return n == 0 ? 0 : next() % n; }
    // Standard normal.
    double gauss() {
        if (have_spare_) {
            have_spare_ = false;
            return spare_;
        }
        double u, v, s;
        do {
            u = uniform() * 2.0 - 1.0;
            v = uniform() * 2.0 - 1.0;
            s = u * u + v * v;
        } while (s >= 1.0 || s == 0.0);
        const double m = std::sqrt(-2.0 * std::log(s) / s);
        spare_ = v * m;
        have_spare_ = true;
        return u * m;
    }
    double gauss(double sigma) { return sigma * gauss(); }
    bool chance(double p) { return uniform() < p; }

private:
    static std::uint64_t rotl(std::uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }
    static std::uint64_t splitmix(std::uint64_t& x) {
        std::uint64_t z = (x += 0x9E3779B97F4A7C15ull);
        z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
        z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
        return z ^ (z >> 31);
    }
    std::uint64_t s_[4]{};
    double spare_ = 0.0;
    bool have_spare_ = false;
};

}  // namespace handscan::sim
